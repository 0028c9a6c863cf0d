// Radix-2 Stockham FFT of FFT_N complex values in shared memory, one butterfly per invocation per
// stage (workgroup size FFT_N / 2), natural order in and out (the autosort needs no bit
// reversal). Expects a constant FFT_N (power of two) in scope. Usage: fill fft_x[0..FFT_N),
// call fft_forward() from every invocation; the result is in fft_x or fft_y as it returns.
#ifndef PENSIGHT_FFT_RADIX2_GLSL
#define PENSIGHT_FFT_RADIX2_GLSL

shared vec2 fft_x[FFT_N];
shared vec2 fft_y[FFT_N];
shared vec2 fft_twiddle[FFT_N / 2];

vec2 cmul(vec2 a, vec2 b) { return vec2(a.x * b.x - a.y * b.y, a.x * b.y + a.y * b.x); }

// Returns true when the result is in fft_x. Contains barriers: call from all invocations.
bool fft_forward() {
  uint i = gl_LocalInvocationID.x;
  const uint half_n = FFT_N / 2u;
  float angle = -6.28318530717958647692 * float(i) / float(FFT_N);
  fft_twiddle[i] = vec2(cos(angle), sin(angle));
  bool in_x = true;
  for (uint p = 1u; p < FFT_N; p <<= 1u) {
    barrier();
    uint k = i & (p - 1u);
    vec2 u0 = in_x ? fft_x[i] : fft_y[i];
    vec2 u1 = cmul(in_x ? fft_x[i + half_n] : fft_y[i + half_n], fft_twiddle[k * (half_n / p)]);
    uint j = (i << 1u) - k;
    if (in_x) {
      fft_y[j] = u0 + u1;
      fft_y[j + p] = u0 - u1;
    } else {
      fft_x[j] = u0 + u1;
      fft_x[j + p] = u0 - u1;
    }
    in_x = !in_x;
  }
  barrier();
  return in_x;
}

#endif
