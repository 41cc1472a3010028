// Compute path drawing: vertex pulling from the generated vertex buffer
// (glDrawElementsIndirect with line strips; gl_VertexID is the index value).
#include "common/constants.h"
#include "common/fiber_vertex.h"
#include "common/view_params.h"

layout(std140, binding = FT_UBO_VIEW_PARAMS) uniform ViewBlock { ViewParams view; };
layout(std430, binding = FT_SSBO_VERTICES) readonly buffer VertexBuffer { FiberVertex vertices[]; };

layout(location = 0) out vec4 fiberPosition;
layout(location = 1) flat out uvec4 fiberId;

void main() {
  FiberVertex v = vertices[gl_VertexID];
  fiberPosition = v.position;
  fiberId = v.id;
  gl_Position = view.viewProj * vec4(v.position.xyz, 1.0);
}
