// bake.cpp — see bake.h.
#include "bake/bake.h"

namespace ft {

std::unique_ptr<Bake> makeBake(std::string_view name) {
  for (const BakeInfo& b : kBakes) {
    if (name != b.name) continue;
    std::unique_ptr<Bake> bake = b.factory();
    bake->name_ = b.name;
    bake->description_ = b.description;
    return bake;
  }
  return nullptr;
}

std::string bakeNames() {
  std::string s;
  for (const BakeInfo& b : kBakes) s += (s.empty() ? "" : ", ") + std::string(b.name);
  return s;
}

}  // namespace ft
