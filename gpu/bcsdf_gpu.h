// bcsdf_gpu.h — the GPU side of the fiber BCSDF (common/bcsdf.h, 000 §4.3):
// bcsdf_eval.comp.glsl evaluates f of eq. 6 (or one lobe) or f_spec of eq. 5
// on lists of angles or directions, and ftAmbientLookup on a table;
// bcsdf_ambient.comp.glsl bakes the ambient table A(θ_o) of eq. 7–10 in float;
// bcsdf_lobe_norm.comp.glsl the lobe-normalisation table Z_p and its lookup.
// One invocation per request or texel, FT_WG_BCSDF per group. Every call
// uploads, dispatches and reads back (waits for the GPU).
#pragma once
#include <epoxy/gl.h>

#include <cstdint>
#include <glm/glm.hpp>
#include <span>
#include <string>
#include <vector>

#include "common/constants.h"
#include "common/fiber_shading.h"
#include "gpu/gl_context.h"
#include "gpu/gl_objects.h"

namespace ft {

// What evaluateAngles / evaluateDirections compute.
struct BcsdfEvalMode {
  static constexpr uint32_t kLobeR = FT_BCSDF_LOBE_R, kLobeTT = FT_BCSDF_LOBE_TT;
  uint32_t model = FT_SHADING_KHUNGURN;  // or FT_SHADING_SIMPLE (common/fiber_shading.h)
  uint32_t lobes = kLobeR | kLobeTT;     // Khungurn: the lobes of eq. 6 summed (both: ftBcsdf itself)
  float ks = 1.0f, beta = 0.0f;          // Simple: k_s and β (radians) of eq. 5
};

class BcsdfGpu {
 public:
  // Midpoint steps of the ambient bake over θ_i ∈ [−π/2, π/2]: π/4096 is
  // 1/23 of the narrowest lobe (β_R = 1°), summed pairwise.
  static constexpr int kAmbientSteps = 4096;

  // defines: extra preprocessor symbols (fault injection, see validation/faults.h).
  explicit BcsdfGpu(const GlInfo& gl, const std::vector<std::string>& defines = {});

  // f at each angle triple (rgb; the simple model repeats f_spec in r, g, b).
  std::vector<glm::vec3> evaluateAngles(const FabricParams& fabric, std::span<const FiberAngles> angles,
                                        const BcsdfEvalMode& mode = {});
  // f of each (t, ω_i, ω_o), through ftFiberAngles on the GPU; spans of one size.
  std::vector<glm::vec3> evaluateDirections(const FabricParams& fabric, std::span<const glm::vec3> tangents,
                                            std::span<const glm::vec3> wi, std::span<const glm::vec3> wo,
                                            const BcsdfEvalMode& mode = {});
  // ftFiberAngles of each (t, ω_i, ω_o) on the GPU.
  std::vector<FiberAngles> fiberAngles(std::span<const glm::vec3> tangents, std::span<const glm::vec3> wi,
                                       std::span<const glm::vec3> wo);
  // A(θ_k), θ_k = ftAmbientTexelAngle(k, texels), in float.
  std::vector<glm::vec3> bakeAmbientTable(const FabricParams& fabric, int texels = FT_AMBIENT_TABLE_SIZE,
                                          int steps = kAmbientSteps);
  // The table looked up at each θ_o: ftAmbientLookup, the two texels, mix.
  std::vector<glm::vec3> lookupAmbient(std::span<const glm::vec3> table, std::span<const float> thetas);
  // (Z_R, Z_TT) at ftLobeNormTexelAngle(k, texels, β_p) (common/bcsdf.h), in float.
  std::vector<glm::vec2> bakeLobeNormTable(const FabricParams& fabric, int texels = FT_LOBE_NORM_TABLE_SIZE);
  // (Z_R, Z_TT) at each θ_i as the frame finds them: ftLobeNormLookup, the
  // two texels of `table` (a bakeLobeNormTable of `fabric`), ftLobeNormFromTable.
  std::vector<glm::vec2> lookupLobeNorm(const FabricParams& fabric, std::span<const glm::vec2> table,
                                        std::span<const float> thetas);

 private:
  // The `kind` uniform of bcsdf_eval.comp.glsl.
  enum Kind : uint32_t { kAngles = 0, kDirections = 1, kDirectionAngles = 2, kLookup = 3 };
  std::vector<glm::vec3> evaluate(const FabricParams& fabric, const std::vector<glm::vec4>& requests, size_t count,
                                  Kind kind, const BcsdfEvalMode& mode);
  static std::vector<glm::vec4> directionRequests(std::span<const glm::vec3> tangents, std::span<const glm::vec3> wi,
                                                  std::span<const glm::vec3> wo);
  void dispatch(GLuint program, size_t items, const char* what);
  std::vector<glm::vec3> readResults(size_t count);

  int maxGroupsY_ = 65535;
  std::vector<glm::vec2> runLobeNorm(const FabricParams& fabric, std::span<const glm::vec2> table,
                                     std::span<const float> thetas, int texels, bool lookup);
  Program evalProgram_, bakeProgram_, lobeNormProgram_;
  Buffer output_;
};

}  // namespace ft
