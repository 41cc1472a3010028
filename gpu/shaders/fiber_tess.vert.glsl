// Tessellation path: no vertex attributes. Each patch has 4 vertices (the
// Catmull-Rom/Bézier control points are fetched from the buffers by the
// control shader); this stage only says which listed segment and which
// instance (block of fiber slots) the patch is.
layout(location = 0) out flat uvec2 vListInstance;
// Added to gl_InstanceID: the capture path issues one single-instance draw
// per block (see FiberGpu::captureTessellation), rendering one instanced draw.
uniform uint instanceOffset;

void main() {
  vListInstance = uvec2(uint(gl_VertexID) / 4u, uint(gl_InstanceID) + instanceOffset);
  gl_Position = vec4(0.0);
}
