// Fused activation selected by the specialization constants ACT, ALPHA, BETA.
#ifndef PENSIGHT_NN_ACT_GLSL
#define PENSIGHT_NN_ACT_GLSL
float activate(float v) {
  if (ACT == 1) return max(v, 0.0);
  if (ACT == 2) return min(max(v, ALPHA), BETA);
  if (ACT == 3) return v >= 0.0 ? v : ALPHA * v;
  if (ACT == 4) return 1.0 / (1.0 + exp(-v));
  if (ACT == 5) return v > 20.0 ? v : log(1.0 + exp(v));
  if (ACT == 6) return sqrt(v);
  return v;
}
#endif
