// flat_dispatch.glsl — GLSL-only include for compute shaders dispatched by
// FiberGpu::dispatchFlat. Not a stage of its own.
// Index of this invocation in a flat dispatch spread over work-group x and y
// (FiberGpu::dispatchFlat; x holds at most 65,535 groups on llvmpipe).
uint flatInvocationIndex(uint groupsX, uint groupSize) {
  return (gl_WorkGroupID.y * groupsX + gl_WorkGroupID.x) * groupSize + gl_LocalInvocationID.x;
}
