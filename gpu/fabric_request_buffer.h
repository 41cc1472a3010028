// fabric_request_buffer.h — the input block of the fabric kernels (the BCSDF's
// and dual scattering's evaluation and bake programs): the fabric, then the
// vec4 requests, in one shader storage buffer.
#pragma once
#include <cstring>
#include <glm/glm.hpp>
#include <vector>

#include "common/bcsdf.h"
#include "gpu/gl_objects.h"

namespace ft {

inline Buffer fabricRequestBuffer(const FabricParams& fabric, const std::vector<glm::vec4>& requests) {
  std::vector<unsigned char> bytes(sizeof(FabricParams) + requests.size() * sizeof(glm::vec4));
  std::memcpy(bytes.data(), &fabric, sizeof(FabricParams));
  if (!requests.empty())
    std::memcpy(bytes.data() + sizeof(FabricParams), requests.data(), requests.size() * sizeof(glm::vec4));
  return Buffer::create(bytes.size(), bytes.data());
}

}  // namespace ft
