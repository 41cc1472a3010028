// Preview shading for the harness images: a Kajiya–Kay style fiber highlight
// from a headlight, and a round-fiber falloff across the strip. Physically
// based fiber shading (§4.3) is a later algorithm of its own.
//
// Depth: a flat camera-facing strip has the depth of its centre line across
// its whole width, so where two thick strips cross (the plies of a twisted
// yarn, a core inside its ply) the nearer centre line wins over the full
// width and the crossing shows as a straight cut. Each fragment is moved
// towards the eye to the surface of the round fiber the strip stands for
// (by halfWidth·sqrt(1 − a²) at a across the strip), so crossings are the
// curved intersections of tubes.
#include "common/constants.h"
#include "common/view_params.h"

layout(std140, binding = FT_UBO_VIEW_PARAMS) uniform ViewBlock { ViewParams view; };
layout(location = 0) in vec3 stripTangent;
layout(location = 1) in float stripAcross;
layout(location = 2) flat in uint stripType;
layout(location = 3) in vec3 stripWorld;
layout(location = 4) in float stripHalfWidth;
layout(location = 0) out vec4 color;

uniform vec3 lightDir;
uniform vec3 baseColor;

void main() {
  vec3 t = normalize(stripTangent);
  float ct = dot(t, normalize(lightDir));
  float diffuse = sqrt(max(1.0 - ct * ct, 0.0));
  float round_ = sqrt(max(1.0 - stripAcross * stripAcross, 0.0));
  vec3 tint = stripType == FT_FIBER_CORE ? baseColor * 0.7 : baseColor;
  color = vec4(tint * (0.25 + 0.75 * diffuse) * (0.5 + 0.5 * round_), 1.0);

  vec3 surface = stripWorld + normalize(view.cameraPos.xyz - stripWorld) * (stripHalfWidth * round_);
  vec4 clip = view.viewProj * vec4(surface, 1.0);
  gl_FragDepth = clamp(0.5 * (clip.z / clip.w) + 0.5, 0.0, 1.0);
}
