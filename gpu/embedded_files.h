// embedded_files.h — the table cmake/EmbedShaders.cmake generates at build time:
// every gpu/shaders/*.glsl as "shaders/<file>" and every common/*.h as "common/<file>".
// Use shader_library.h to look files up; this is the raw data.
#pragma once
#include <cstddef>

namespace ft::detail {

struct EmbeddedFile {
  const char* name;
  const char* text;  // NUL-terminated
  std::size_t size;  // bytes, without the NUL
};

// kEmbeddedFileCount entries, then a {nullptr, nullptr, 0} sentinel.
extern const EmbeddedFile kEmbeddedFiles[];
extern const std::size_t kEmbeddedFileCount;

}  // namespace ft::detail
