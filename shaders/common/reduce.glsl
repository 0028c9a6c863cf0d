// Workgroup-wide float sum for a workgroup of N invocations (any shape). Sums reduce within each
// subgroup first, so one call costs two barriers instead of log2(N). Every invocation must call
// it (it contains barriers) and all receive the total. The including shader must enable
// GL_KHR_shader_subgroup_arithmetic.
#ifndef PENSIGHT_REDUCE_GLSL
#define PENSIGHT_REDUCE_GLSL

#define PENSIGHT_DEFINE_WORKGROUP_SUM(N)                                  \
  shared float pensight_partial[N];                                       \
  float workgroup_sum(float v) {                                          \
    float s = subgroupAdd(v);                                             \
    if (subgroupElect()) pensight_partial[gl_SubgroupID] = s;             \
    barrier();                                                            \
    float total = 0.0;                                                    \
    for (uint i = 0; i < gl_NumSubgroups; ++i) total += pensight_partial[i]; \
    barrier();                                                            \
    return total;                                                         \
  }

#endif
