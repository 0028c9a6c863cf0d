// Flat invocation index for 1-D work dispatched as a 2-D grid (x <= 65535 groups of 256).
#ifndef PENSIGHT_NN_INDEX_GLSL
#define PENSIGHT_NN_INDEX_GLSL
uint flat_index() {
  return (gl_WorkGroupID.y * gl_NumWorkGroups.x + gl_WorkGroupID.x) * 256u +
         gl_LocalInvocationID.x;
}
#endif
