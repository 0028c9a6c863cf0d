// Workgroup-wide float sum over a shared array of local_size_x (a power of two) elements.
// Every invocation must call it (it contains barriers); all receive the total.
#ifndef PENSIGHT_REDUCE_GLSL
#define PENSIGHT_REDUCE_GLSL

#define PENSIGHT_DEFINE_WORKGROUP_SUM(N)                     \
  shared float pensight_partial[N];                          \
  float workgroup_sum(float v) {                             \
    uint lid = gl_LocalInvocationID.x;                       \
    pensight_partial[lid] = v;                               \
    barrier();                                               \
    for (uint s = N / 2; s > 0; s >>= 1) {                   \
      if (lid < s) pensight_partial[lid] += pensight_partial[lid + s]; \
      barrier();                                             \
    }                                                        \
    float total = pensight_partial[0];                       \
    barrier();                                               \
    return total;                                            \
  }

#endif
