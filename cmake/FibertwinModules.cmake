# One helper per kind of module, so adding an algorithm is one line.

# Flags every fibertwin target gets. -ffp-contract=off: the GLSL side marks the
# values whose rounding matters `precise`; the CPU side must not fuse either.
function(ft_target_defaults target)
  target_compile_options(${target} PRIVATE -Wall -Wextra -Wno-missing-field-initializers -ffp-contract=off
                                           -fno-fast-math)
  # GCC 12 has no <format>: fmt is the formatting library everywhere.
  target_link_libraries(${target} PRIVATE fmt::fmt)
  if(FT_SANITIZE)
    target_compile_options(${target} PRIVATE -fsanitize=address,undefined -fno-omit-frame-pointer)
    target_link_options(${target} PRIVATE -fsanitize=address,undefined)
  endif()
endfunction()

# ft_add_library(name SOURCES ... DEPS ...): a static library of the project.
function(ft_add_library name)
  cmake_parse_arguments(ARG "" "" "SOURCES;DEPS;PRIVATE_DEPS" ${ARGN})
  add_library(${name} STATIC ${ARG_SOURCES})
  target_include_directories(${name} PUBLIC ${PROJECT_SOURCE_DIR})
  target_link_libraries(${name} PUBLIC ${ARG_DEPS} PRIVATE ${ARG_PRIVATE_DEPS})
  ft_target_defaults(${name})
endfunction()

# ft_add_test(name SOURCES ... DEPS ... [LABELS ...] [TIMEOUT s]): a GoogleTest
# program registered with ctest, one ctest entry per test case.
function(ft_add_test name)
  cmake_parse_arguments(ARG "" "TIMEOUT" "SOURCES;DEPS;LABELS" ${ARGN})
  add_executable(${name} ${ARG_SOURCES})
  target_link_libraries(${name} PRIVATE ${ARG_DEPS} GTest::gtest GTest::gtest_main)
  ft_target_defaults(${name})
  if(NOT ARG_TIMEOUT)
    set(ARG_TIMEOUT 300)
  endif()
  include(GoogleTest)
  gtest_discover_tests(${name} WORKING_DIRECTORY ${PROJECT_SOURCE_DIR} DISCOVERY_TIMEOUT 60
                       PROPERTIES TIMEOUT ${ARG_TIMEOUT} LABELS "${ARG_LABELS}"
                                  ENVIRONMENT "FT_SOURCE_DIR=${PROJECT_SOURCE_DIR}"
                                  ENVIRONMENT_MODIFICATION "FT_SHARED_DIR=set:${PROJECT_SOURCE_DIR}/../shared")
endfunction()

# ft_add_benchmark(name SOURCES ... DEPS ...): a Google Benchmark program.
function(ft_add_benchmark name)
  cmake_parse_arguments(ARG "" "" "SOURCES;DEPS" ${ARGN})
  add_executable(${name} ${ARG_SOURCES})
  target_link_libraries(${name} PRIVATE ${ARG_DEPS} benchmark::benchmark)
  ft_target_defaults(${name})
endfunction()

# ft_embed_text(out_var file symbol): generates a .cpp defining
# `extern const char symbol[]` with the file's bytes (NUL-terminated) and
# returns the source in out_var. Rebuilt when the file changes.
function(ft_embed_text out_var file symbol)
  set(out ${CMAKE_CURRENT_BINARY_DIR}/${symbol}.cpp)
  add_custom_command(OUTPUT ${out}
    COMMAND ${CMAKE_COMMAND} -DIN=${file} -DOUT=${out} -DSYMBOL=${symbol} -P ${PROJECT_SOURCE_DIR}/cmake/EmbedText.cmake
    DEPENDS ${file} ${PROJECT_SOURCE_DIR}/cmake/EmbedText.cmake VERBATIM)
  set(${out_var} ${out} PARENT_SCOPE)
endfunction()
