#!/usr/bin/env bash
# Quick start (2): install what is missing, build, and run every test suite:
#   1. release build: every ctest (CPU units, GPU kernels on llvmpipe, the
#      harness on the default scene and on glove.bcc, fault injection, shaders
#      through glslangValidator);
#   2. AddressSanitizer + UBSan build: the input readers (BCC, presets, stitch
#      meshes), the command line on malformed files, the GPU kernels' host code
#      and the harness on the built-in scene (labels input and asan); Debug
#      at -O0: -O1 ran the ASan harness 2.4x faster (validate_default 272 ->
#      168 s) but its build took 592 s against 251 s, more than it saved
#      (CI 1,758 s against 1,353 s, 2026-12-03); line tables only (-g1, as
#      the release build): ASan's reports keep file and line, the build
#      takes ~15 % less (the asan preset itself keeps -g for debuggers);
#   3. clang libFuzzer build: bounded fuzz runs of the BCC reader and of stitch-mesh
#      OBJ text through the knit host side.
# The release and ASan builds here are unity builds (CMAKE_UNITY_BUILD: the
# sources of each library compiled in batches, ~20 % less build time on 2
# cores; the presets themselves build file by file, which keeps a developer's
# incremental rebuilds short). So two .cpp files of one library must not
# define the same name in their anonymous namespaces: shared helpers live in
# a header (validation/case_support.h, reference/numbers.h, ...).
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install-deps.sh
jobs=$(nproc)

echo "== release build and tests"
cmake --preset release -DCMAKE_UNITY_BUILD=ON
cmake --build --preset release
ctest --preset release -j "$jobs"

echo "== AddressSanitizer + UBSan: input handling, GPU host code, the harness"
cmake --preset asan -DCMAKE_UNITY_BUILD=ON -DCMAKE_C_FLAGS_DEBUG=-g1 -DCMAKE_CXX_FLAGS_DEBUG=-g1
cmake --build --preset asan --target bcc_reader_test yarn_preset_test yarn_radius_test stitch_mesh_test knit_solver_test knit_gpu_test fiber_gpu_test fibertwin \
  edge_corpus_test draw_check_test
# Leak checking is off: Mesa's driver keeps allocations alive until exit.
ASAN_OPTIONS=detect_leaks=0 ctest --preset asan -L "input|asan" -j "$jobs"

echo "== libFuzzer: bounded runs of the BCC reader and the stitch-mesh reader + knit setup"
cmake --preset fuzz
cmake --build --preset fuzz --target bcc_fuzzer stitch_obj_fuzzer
ctest --preset fuzz -L fuzz -j "$jobs"
