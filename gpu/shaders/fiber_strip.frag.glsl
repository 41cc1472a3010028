// Preview shading for the harness images: a Kajiya–Kay style fiber highlight
// from a headlight, and a round-fiber falloff across the strip. Physically
// based fiber shading (§4.3) is a later algorithm of its own.
#include "common/constants.h"
#include "common/view_params.h"

layout(std140, binding = FT_UBO_VIEW_PARAMS) uniform ViewBlock { ViewParams view; };
layout(location = 0) in vec3 stripTangent;
layout(location = 1) in float stripAcross;
layout(location = 2) flat in uint stripType;
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
}
