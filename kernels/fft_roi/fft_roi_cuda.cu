// CUDA path of the FFT ROI stage: extract (resample + normalise + window + energy centroid),
// cuFFT batched r2c (planned once per batch size), peak search. The kernels mirror
// shaders/fft_roi/{extract,peaks}.comp and analyze_spectrum() step by step.
#include <cufft.h>

#include <numbers>
#include <string>

#include "core/error.h"
#include "kernels/fft_roi/fft_roi.h"
#include "runtime/cuda_check.cuh"
#include "runtime/cuda_reduce.cuh"

namespace pensight::kernels {
namespace {

constexpr int kThreads = 256;

void check_cufft(cufftResult r, const char* call) {
  if (r != CUFFT_SUCCESS) {
    throw Error(std::string(call) + " failed with cufftResult " + std::to_string(int(r)));
  }
}

// Argmax over the block; ties go to the lower index; -1 when no thread had a candidate.
__device__ int block_argmax(float v, int index, float* value, int* idx) {
  value[threadIdx.x] = v;
  idx[threadIdx.x] = index;
  __syncthreads();
  for (int s = kThreads / 2; s > 0; s /= 2) {
    if (threadIdx.x < s) {
      const float a = value[threadIdx.x], b = value[threadIdx.x + s];
      if (b > a || (b == a && idx[threadIdx.x + s] < idx[threadIdx.x])) {
        value[threadIdx.x] = b;
        idx[threadIdx.x] = idx[threadIdx.x + s];
      }
    }
    __syncthreads();
  }
  const int winner = value[0] > 0.0f ? idx[0] : -1;
  __syncthreads();
  return winner;
}

struct ExtractArgs {
  const uint8_t* image;
  int width;
  const RoiOrigin* rois;
  int roi, n;
  bool window;
  float* samples;
  RoiLattice* lattices;
};

// [1 2 1]/4 binomial convolved with linear interpolation (see Taps in fft_roi_cpu.cpp).
__device__ void taps(int u, const ExtractArgs& a, int index[4], float weight[4]) {
  const float x = (u + 0.5f) * (float(a.roi) / float(a.n)) - 0.5f;
  const float fl = floorf(x);
  const float f = x - fl;
  const int i = int(fl);
  for (int j = 0; j < 4; ++j) index[j] = min(max(i - 1 + j, 0), a.roi - 1);
  weight[0] = (1.0f - f) / 4.0f;
  weight[1] = (2.0f - f) / 4.0f;
  weight[2] = (1.0f + f) / 4.0f;
  weight[3] = f / 4.0f;
}

__device__ float window_at(int u, const ExtractArgs& a) {
  if (!a.window) return 1.0f;
  const float s = sinpif((u + 0.5f) / float(a.n));
  return s * s;
}

__device__ float resample(const ExtractArgs& a, RoiOrigin o, int u, int v) {
  auto px = [&](int x, int y) { return float(a.image[(o.y + y) * a.width + o.x + x]); };
  if (a.n == a.roi) return px(u, v);
  int ix[4], iy[4];
  float wx[4], wy[4];
  taps(u, a, ix, wx);
  taps(v, a, iy, wy);
  float result = 0.0f;
  for (int j = 0; j < 4; ++j) {
    float row = 0.0f;
    for (int i = 0; i < 4; ++i) row += wx[i] * px(ix[i], iy[j]);
    result += wy[j] * row;
  }
  return result;
}

__global__ void extract_kernel(ExtractArgs a) {
  __shared__ float partial[kThreads];
  const RoiOrigin o = a.rois[blockIdx.x];
  const int count = a.n * a.n;
  float* dst = a.samples + size_t(blockIdx.x) * count;
  float s = 0;
  for (int i = threadIdx.x; i < count; i += kThreads) {
    const float v = resample(a, o, i % a.n, i / a.n);
    dst[i] = v;
    s += v;
  }
  const float mean = cuda::block_sum<kThreads>(s, partial) / count;
  float q = 0;
  for (int i = threadIdx.x; i < count; i += kThreads) q += (dst[i] - mean) * (dst[i] - mean);
  const float var = cuda::block_sum<kThreads>(q, partial) / count;
  const float inv_std = var > kFlatVariance ? rsqrtf(var) : 0.0f;
  // Block by block (16 x 16 blocks, one per thread): local contrast energy centroid, as in
  // shaders/fft_roi/extract.comp. __syncthreads() in block_sum made the samples visible.
  const int bx = threadIdx.x % 16, by = threadIdx.x / 16;
  const int u0 = bx * a.n / 16, u1 = (bx + 1) * a.n / 16;
  const int v0 = by * a.n / 16, v1 = (by + 1) * a.n / 16;
  float sum = 0, sq = 0;
  for (int v = v0; v < v1; ++v) {
    for (int u = u0; u < u1; ++u) {
      const float x = (dst[v * a.n + u] - mean) * (window_at(v, a) * inv_std * window_at(u, a));
      dst[v * a.n + u] = x;
      sum += x;
      sq += x * x;
    }
  }
  float e = fmaxf(0.0f, sq - sum * sum / float((v1 - v0) * (u1 - u0)));
  float eu = e * 0.5f * float(u0 + u1 - 1), ev = e * 0.5f * float(v0 + v1 - 1);
  e = cuda::block_sum<kThreads>(e, partial);
  eu = cuda::block_sum<kThreads>(eu, partial);
  ev = cuda::block_sum<kThreads>(ev, partial);
  if (threadIdx.x == 0) {
    const float centre = 0.5f * (a.n - 1), scale = float(a.roi) / float(a.n);
    a.lattices[blockIdx.x].centroid_dx = e > 0 ? (eu / e - centre) * scale : 0.0f;
    a.lattices[blockIdx.x].centroid_dy = e > 0 ? (ev / e - centre) * scale : 0.0f;
  }
}

struct PeakArgs {
  const cufftComplex* spectrum;
  int n, roi;
  float r2_min, r2_max, cos2_max, subharmonic;
  bool subbin;
  float beyond_band_ratio, below_band_ratio;
  RoiLattice* lattices;
};

struct Spec {
  const cufftComplex* s;
  int n, w;
  __device__ float power(int kx, int ky) const {
    if (kx < 0) kx = -kx, ky = -ky;
    const cufftComplex c = s[(ky & (n - 1)) * w + kx];
    return c.x * c.x + c.y * c.y;
  }
  __device__ int2 bin(int index) const {
    const int row = index / w;
    return make_int2(index % w, row < n / 2 ? row : row - n);
  }
};

__device__ bool in_band(const PeakArgs& a, int kx, int ky) {
  if (kx == 0 && ky <= 0) return false;
  const float r2 = float(kx * kx + ky * ky);
  return r2 >= a.r2_min && r2 <= a.r2_max;
}

// Between the band and the Nyquist circle.
__device__ bool beyond_band(const PeakArgs& a, int kx, int ky) {
  if (kx == 0 && ky <= 0) return false;
  const float r2 = float(kx * kx + ky * ky);
  return r2 > a.r2_max && r2 <= float((a.n / 2) * (a.n / 2));
}

// radial_floor() in fft_roi_peaks.cpp.
__device__ float radial_floor(const Spec& s, int2 b) {
  const int ax = abs(b.x), ay = abs(b.y), r = max(ax, ay);
  const int sx = b.x < 0 ? -1 : 1, sy = b.y < 0 ? -1 : 1;
  float floor_v = 0.0f;
  for (int k = 0; k < 2; ++k) {
    const int offset = k == 0 ? kRidgeOffset0 : kRidgeOffset1;
    for (int side = -1; side <= 1; side += 2) {
      const int m = r + side * offset;
      if (m < kMinCoarseCycles) continue;
      const int x = (2 * ax * m + r) / (2 * r), y = (2 * ay * m + r) / (2 * r);
      floor_v = fmaxf(floor_v, s.power(sx * x, sy * y));
    }
  }
  return floor_v;
}

__device__ int2 fundamental(const PeakArgs& a, const Spec& s, int2 p) {
  const float pp = s.power(p.x, p.y);
  const int hx = int(floorf(p.x * 0.5f + 0.5f)), hy = int(floorf(p.y * 0.5f + 0.5f));
  if (float(hx * hx + hy * hy) < a.r2_min) return p;
  int2 best = make_int2(0, 0);
  float best_v = -1.0f;
  for (int dy = -1; dy <= 1; ++dy)
    for (int dx = -1; dx <= 1; ++dx) {
      const float v = s.power(hx + dx, hy + dy);
      if (v > best_v) best_v = v, best = make_int2(hx + dx, hy + dy);
    }
  if (!(best_v >= a.subharmonic * pp)) return p;
  for (int dy = -1; dy <= 1; ++dy)
    for (int dx = -1; dx <= 1; ++dx)
      if (s.power(best.x + dx, best.y + dy) > best_v) return p;
  if (!(best_v >= kRidgeProminence * radial_floor(s, best))) return p;
  if (best.x < 0 || (best.x == 0 && best.y < 0)) best = make_int2(-best.x, -best.y);
  return best;
}

// The lattice at p is the second harmonic of a coarser one below the band (as
// coarser_than_band() in fft_roi_peaks.cpp).
__device__ bool coarser_than_band(const PeakArgs& a, const Spec& s, int2 p) {
  const float pp = s.power(p.x, p.y);
  int2 best = make_int2(0, 0);
  float best_v = -1.0f;
  for (int y2 = p.y - 1; y2 <= p.y + 1; ++y2)
    for (int x2 = p.x - 1; x2 <= p.x + 1; ++x2) {
      if (y2 % 2 != 0 || x2 % 2 != 0) continue;
      const float v = s.power(x2 / 2, y2 / 2);
      if (v > best_v) best_v = v, best = make_int2(x2 / 2, y2 / 2);
    }
  const int r2 = best.x * best.x + best.y * best.y;
  if (float(r2) >= a.r2_min || r2 < kMinCoarseCycles * kMinCoarseCycles ||
      !(best_v >= a.below_band_ratio * pp))
    return false;
  for (int dy = -1; dy <= 1; ++dy)
    for (int dx = -1; dx <= 1; ++dx)
      if (s.power(best.x + dx, best.y + dy) > best_v) return false;
  return true;
}

__device__ float vertex(float lm, float l0, float lp) {
  const float denom = lm - 2.0f * l0 + lp;
  if (!(denom < 0.0f)) return 0.0f;
  return fminf(0.5f, fmaxf(-0.5f, 0.5f * (lm - lp) / denom));
}

__device__ float2 refine(const PeakArgs& a, const Spec& s, int2 b) {
  float dx = 0, dy = 0;
  if (a.subbin) {
    auto lp = [&](int kx, int ky) { return logf(fmaxf(s.power(kx, ky), 1e-30f)); };
    const float l0 = lp(b.x, b.y);
    dx = vertex(lp(b.x - 1, b.y), l0, lp(b.x + 1, b.y));
    dy = vertex(lp(b.x, b.y - 1), l0, lp(b.x, b.y + 1));
  }
  const float fx = (b.x + dx) / a.roi, fy = (b.y + dy) / a.roi;
  // A peak on the kx = 0 column may refine to kx < 0: back to the half plane.
  return (fx < 0 || (fx == 0 && fy < 0)) ? make_float2(-fx, -fy) : make_float2(fx, fy);
}

__device__ float energy3x3(const Spec& s, int2 b) {
  float e = 0;
  for (int dy = -1; dy <= 1; ++dy)
    for (int dx = -1; dx <= 1; ++dx) e += s.power(b.x + dx, b.y + dy);
  return e;
}

__global__ void peaks_kernel(PeakArgs a) {
  __shared__ float partial[kThreads];
  __shared__ float value[kThreads];
  __shared__ int idx[kThreads];
  const int w = a.n / 2 + 1;
  const Spec s{a.spectrum + size_t(blockIdx.x) * a.n * w, a.n, w};
  const int total = a.n * w;
  float energy = 0, count = 0, v1 = -1, vb = -1;
  int i1 = 0, ib = 0;
  for (int i = threadIdx.x; i < total; i += kThreads) {
    const int2 k = s.bin(i);
    if (!in_band(a, k.x, k.y)) {
      if (beyond_band(a, k.x, k.y)) {
        const float v = s.power(k.x, k.y);
        if (v > vb) vb = v, ib = i;
      }
      continue;
    }
    const float v = s.power(k.x, k.y);
    energy += v;
    count += 1;
    if (v > v1) v1 = v, i1 = i;
  }
  energy = cuda::block_sum<kThreads>(energy, partial);
  count = cuda::block_sum<kThreads>(count, partial);
  const int w1 = block_argmax(v1, i1, value, idx);
  const int wb = block_argmax(vb, ib, value, idx);
  bool too_fine = false;
  if (w1 >= 0 && wb >= 0) {
    const int2 k1 = s.bin(w1), kb = s.bin(wb);
    too_fine = s.power(kb.x, kb.y) > a.beyond_band_ratio * s.power(k1.x, k1.y);
  }
  RoiLattice& out = a.lattices[blockIdx.x];
  float r[6] = {0, 0, 0, 0, 0, 0};
  if (w1 >= 0 && count > 0 && !too_fine) {
    const int2 p1 = fundamental(a, s, s.bin(w1));
    const bool coarse = coarser_than_band(a, s, p1);
    const float p1_r2 = float(p1.x * p1.x + p1.y * p1.y);
    float v2 = -1;
    int i2 = 0;
    for (int i = threadIdx.x; i < total; i += kThreads) {
      const int2 k = s.bin(i);
      if (!in_band(a, k.x, k.y)) continue;
      const float dot = float(k.x * p1.x + k.y * p1.y);
      if (dot * dot >= a.cos2_max * float(k.x * k.x + k.y * k.y) * p1_r2) continue;
      const float v = s.power(k.x, k.y);
      if (v > v2) v2 = v, i2 = i;
    }
    const int w2 = block_argmax(v2, i2, value, idx);
    const int2 p2 = w2 >= 0 ? fundamental(a, s, s.bin(w2)) : make_int2(0, 0);
    if (w2 >= 0 && !coarse && !coarser_than_band(a, s, p2)) {
      float2 f1 = refine(a, s, p1), f2 = refine(a, s, p2);
      if (atan2f(f1.y, f1.x) > atan2f(f2.y, f2.x)) {
        const float2 t = f1;
        f1 = f2;
        f2 = t;
      }
      r[0] = f1.x, r[1] = f1.y, r[2] = f2.x, r[3] = f2.y;
      r[4] = fminf(1.0f, (energy3x3(s, p1) + energy3x3(s, p2)) / energy);
      r[5] = fminf(s.power(p1.x, p1.y), s.power(p2.x, p2.y)) / (energy / count);
    }
  }
  if (threadIdx.x == 0) {
    out.f1x = r[0], out.f1y = r[1], out.f2x = r[2], out.f2y = r[3];
    out.quality = r[4], out.contrast = r[5];
  }
}

}  // namespace

struct FftRoiCuda::Impl {
  FftRoiShape shape;
  PeakParams params;
  int max_rois;
  cuda::DeviceArray<uint8_t> image;
  cuda::DeviceArray<RoiOrigin> rois;
  cuda::DeviceArray<float> samples;
  cuda::DeviceArray<cufftComplex> spectrum;
  cuda::DeviceArray<RoiLattice> lattices;
  cufftHandle plan = 0;
  int planned = 0;  // batch size of `plan`

  Impl(const FftRoiShape& s, const PeakParams& p, int max)
      : shape(s),
        params(p),
        max_rois(max),
        image(size_t(s.width) * s.height),
        rois(max),
        samples(size_t(max) * s.fft_size * s.fft_size),
        spectrum(size_t(max) * s.fft_size * (s.fft_size / 2 + 1)),
        lattices(max) {}
  ~Impl() {
    if (planned) cufftDestroy(plan);
  }

  void plan_for(int batch) {
    if (batch == planned) return;
    if (planned) cufftDestroy(plan);
    planned = 0;
    int n[2] = {shape.fft_size, shape.fft_size};
    const int w = shape.fft_size / 2 + 1;
    check_cufft(cufftPlanMany(&plan, 2, n, nullptr, 1, shape.fft_size * shape.fft_size, nullptr, 1,
                              shape.fft_size * w, CUFFT_R2C, batch),
                "cufftPlanMany");
    planned = batch;
  }
};

FftRoiCuda::FftRoiCuda(const FftRoiShape& shape, const PeakParams& params, int max_rois) {
  validate(shape, FftSizes::kPowerOfTwo);
  if (max_rois < 1) throw Error("FftRoiCuda: max_rois must be >= 1");
  impl_ = std::make_unique<Impl>(shape, params, max_rois);
  impl_->plan_for(max_rois);
}

FftRoiCuda::~FftRoiCuda() = default;
FftRoiCuda::FftRoiCuda(FftRoiCuda&&) noexcept = default;
FftRoiCuda& FftRoiCuda::operator=(FftRoiCuda&&) noexcept = default;

std::vector<RoiLattice> FftRoiCuda::run(const ImageU8& image, std::span<const RoiOrigin> rois) {
  Impl& m = *impl_;
  if (image.width != m.shape.width || image.height != m.shape.height) {
    throw Error("FftRoiCuda::run: image is " + std::to_string(image.width) + "x" +
                std::to_string(image.height) + ", the stage was built for " +
                std::to_string(m.shape.width) + "x" + std::to_string(m.shape.height));
  }
  validate(m.shape, rois);
  if (rois.empty()) return {};
  if (static_cast<int>(rois.size()) > m.max_rois) {
    throw Error("FftRoiCuda::run: " + std::to_string(rois.size()) + " ROIs, built for at most " +
                std::to_string(m.max_rois));
  }
  const int count = static_cast<int>(rois.size());
  m.plan_for(count);
  m.image.upload(image.pixels.data(), image.pixels.size());
  m.rois.upload(rois.data(), rois.size());
  extract_kernel<<<count, kThreads>>>({m.image.data(), m.shape.width, m.rois.data(),
                                       m.shape.roi_size_px, m.shape.fft_size, m.shape.window,
                                       m.samples.data(), m.lattices.data()});
  PENSIGHT_CUDA(cudaGetLastError());
  check_cufft(cufftExecR2C(m.plan, m.samples.data(), m.spectrum.data()), "cufftExecR2C");
  const float r_max = m.params.max_nyquist_share * float(m.shape.fft_size / 2);
  const float c = cosf(m.params.min_angle_deg * std::numbers::pi_v<float> / 180.0f);
  peaks_kernel<<<count, kThreads>>>(
      {m.spectrum.data(), m.shape.fft_size, m.shape.roi_size_px,
       m.params.min_cycles * m.params.min_cycles, r_max * r_max, c * c, m.params.subharmonic_ratio,
       m.params.subbin, m.params.beyond_band_ratio, m.params.below_band_ratio, m.lattices.data()});
  PENSIGHT_CUDA(cudaGetLastError());
  std::vector<RoiLattice> out(rois.size());
  m.lattices.download(out.data(), out.size());
  PENSIGHT_CUDA(cudaDeviceSynchronize());
  return out;
}

}  // namespace pensight::kernels
