// Body of shaders/nn/<name>.comp and <name>_f16.comp (STORE: see nn_types.glsl).
#include "nn_types.glsl"
// Batched C = alpha * A x B + beta * bias, 16x16 output tiles through shared memory. Strides make
// transposes and broadcast batch/bias free: A[b, m, k] = a[b*sab + m*sam + k*sak], etc.
layout(local_size_x = 16, local_size_y = 16) in;
layout(std430, binding = 0) readonly buffer A { STORE a[]; };
layout(std430, binding = 1) readonly buffer B { STORE b[]; };
layout(std430, binding = 2) readonly buffer Cb { STORE bias[]; };
layout(std430, binding = 3) writeonly buffer Y { STORE y[]; };
layout(push_constant) uniform Push {
  uint M, N, K;
  uint sab, sam, sak, sbb, sbk, sbn, scm, scn;
  float alpha, beta;
};
shared float ta[16][17];
shared float tb[16][17];
void main() {
  uint lx = gl_LocalInvocationID.x, ly = gl_LocalInvocationID.y;
  uint n = gl_WorkGroupID.x * 16 + lx, m = gl_WorkGroupID.y * 16 + ly, bt = gl_WorkGroupID.z;
  float acc = 0.0;
  for (uint k0 = 0; k0 < K; k0 += 16) {
    uint ka = k0 + lx, kb = k0 + ly;
    ta[ly][lx] = (m < M && ka < K) ? LD(a[bt * sab + m * sam + ka * sak]) : 0.0;
    tb[ly][lx] = (n < N && kb < K) ? LD(b[bt * sbb + kb * sbk + n * sbn]) : 0.0;
    barrier();
    for (uint k = 0; k < 16; ++k) acc += ta[ly][k] * tb[k][lx];
    barrier();
  }
  if (m < M && n < N) y[(bt * M + m) * N + n] = ST(alpha * acc + beta * LD(bias[m * scm + n * scn]));
}
