// stitch_obj_fuzzer.cpp — libFuzzer target for stitch-mesh OBJ text through
// the knit pipeline's host side: parseStitchObj, then, for an accepted mesh,
// buildKnitSetup (rest = the mesh, deformed = the mesh sheared 20°) and the
// double Gauss–Newton solve of every tile. Only InputError may escape; an
// accepted mesh must give finite problems and finite solved points (a NaN
// handed to the renderer is a bug as much as a crash).
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <string_view>

#include "knit/knit_problem.h"
#include "knit/stitch_mesh.h"
#include "scene/input_error.h"

namespace {

void check(bool ok) {
  if (!ok) __builtin_trap();
}

bool finite(const glm::dvec3& p) { return std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z); }

void solveAll(const ft::KnitSetup& s) {
  check(s.frames.size() == s.problems.size());
  for (const ft::KnitYarn& y : s.yarns)
    for (uint32_t p : y.points) check(p < s.tileCount() * FT_KNIT_TILE_POINTS);
  for (uint32_t t = 0; t < s.tileCount(); ++t) {
    const ft::knit64::KnitTileResult r =
        ft::knit64::knitSolveTile(s.problems[t], s.options.wAngle, s.options.wLength, 3u);
    for (int i = 0; i < FT_KNIT_TILE_POINTS; ++i) check(finite(r.p[i]));
    for (int k = 0; k < 3; ++k) check(r.energy[k + 1] <= r.energy[k] * (1 + 1e-9) + 1e-300);
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  ft::StitchMesh mesh;
  try {
    mesh = ft::parseStitchObj(text, "fuzz.obj");
  } catch (const ft::InputError&) {
    return 0;
  }
  if (mesh.faces.size() > 64) return 0;  // keep each input fast; size is not what is being tested
  for (const ft::Deformation& d : {ft::Deformation{}, ft::Deformation{ft::Deformation::Shear, 20.0}}) {
    try {
      solveAll(ft::buildKnitSetup(mesh, ft::deform(mesh, d), {}));
    } catch (const ft::InputError&) {
    }
  }
  return 0;
}
