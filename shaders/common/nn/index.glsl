// 1-D work over `count` elements: a grid-stride loop, so the host may launch fewer workgroups
// than count / 256 (CPU Vulkan drivers pay a fixed cost per workgroup).
#ifndef PENSIGHT_NN_INDEX_GLSL
#define PENSIGHT_NN_INDEX_GLSL
uint flat_index() {
  return (gl_WorkGroupID.y * gl_NumWorkGroups.x + gl_WorkGroupID.x) * 256u +
         gl_LocalInvocationID.x;
}
uint flat_stride() {
  return gl_NumWorkGroups.x * gl_NumWorkGroups.y * 256u;
}
#endif
