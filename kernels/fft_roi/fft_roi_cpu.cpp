#include <fftw3.h>
#include <omp.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <mutex>
#include <string>

#include "kernels/fft_roi/fft_roi.h"
#include "runtime/error.h"

namespace pensight::kernels {
namespace {

// FFTW's planner is not thread-safe; execution of a finished plan is.
std::mutex& planner_mutex() {
  static std::mutex m;
  return m;
}

struct FftwFree {
  void operator()(void* p) const { fftwf_free(p); }
};
template <class T>
using FftwArray = std::unique_ptr<T[], FftwFree>;

template <class T>
FftwArray<T> fftw_array(size_t count) {
  auto* p = static_cast<T*>(fftwf_malloc(count * sizeof(T)));
  if (!p) throw Error("fft_roi: out of memory for FFTW buffers");
  return FftwArray<T>(p);
}

// Resampling taps per output index u (sample u sits at x = (u + 0.5) * roi / fft - 0.5): a [1 2
// 1]/4 binomial prefilter convolved with the linear interpolation, i.e. four source taps floor(x) -
// 1 .. floor(x) + 2, clamped to the ROI. Plain bilinear lets the spectral image of a lattice near
// the pixel Nyquist (300 - f cycles per ROI) through, which the decimation to 256 folds into the
// band as a false, coarser lattice; the binomial zero at 0.5 cycles/px removes it.
struct Taps {
  std::vector<std::array<int, 4>> index;  // clamped source indices
  std::vector<int> first;                 // floor(x) - 1 + kPad: first tap in a padded row
  std::vector<std::array<float, 4>> weight;
};
// Edge replication on each side of a padded row, so that the four taps are consecutive.
constexpr int kPad = 2;

Taps taps(int roi, int n) {
  Taps t;
  const double scale = static_cast<double>(roi) / n;
  for (int u = 0; u < n; ++u) {
    const double x = (u + 0.5) * scale - 0.5;
    const int i = static_cast<int>(std::floor(x));
    const auto f = static_cast<float>(x - i);
    std::array<int, 4> index;
    for (int j = 0; j < 4; ++j) index[j] = std::clamp(i - 1 + j, 0, roi - 1);
    t.index.push_back(index);
    t.first.push_back(i - 1 + kPad);
    t.weight.push_back({(1 - f) / 4, (2 - f) / 4, (1 + f) / 4, f / 4});
  }
  return t;
}

}  // namespace

// Must match the 16 x 16 blocks of shaders/fft_roi/extract.comp (one per invocation).
constexpr int kCentroidBlocks = 16;

struct FftRoiCpu::Impl {
  FftRoiShape shape;
  PeakParams params;
  int threads;
  size_t nn, nc;
  Taps taps;
  std::vector<float> window;
  fftwf_plan plan = nullptr;
  // Per-thread scratch: one ROI of samples and its spectrum.
  std::vector<FftwArray<float>> in;
  std::vector<FftwArray<fftwf_complex>> out;
  std::vector<std::vector<float>> rows;  // one source row, vertically blended

  ~Impl() {
    if (plan) {
      std::lock_guard lock(planner_mutex());
      fftwf_destroy_plan(plan);
    }
  }

  // Resample (separable: a vertical blend of four source rows, then four horizontal taps),
  // then zero mean / unit variance and the window. Sums use 8 float lanes per row (vectorised)
  // and double across rows.
  // Returns the energy centroid of the result, in image pixels from the ROI centre.
  std::pair<float, float> prepare_one(const ImageU8& image, RoiOrigin o, float* dst,
                                      float* row_buf) const {
    const int n = shape.fft_size, roi = shape.roi_size;
    const bool identity = n == roi;
    double sum = 0;
    for (int v = 0; v < n; ++v) {
      float* row = dst + static_cast<size_t>(v) * n;
      if (identity) {
        const uint8_t* src = &image.at(o.x, o.y + v);
        for (int u = 0; u < n; ++u) row[u] = src[u];
      } else {
        const std::array<int, 4>& iy = taps.index[v];
        const std::array<float, 4>& wy = taps.weight[v];
        const uint8_t* r0 = &image.at(o.x, o.y + iy[0]);
        const uint8_t* r1 = &image.at(o.x, o.y + iy[1]);
        const uint8_t* r2 = &image.at(o.x, o.y + iy[2]);
        const uint8_t* r3 = &image.at(o.x, o.y + iy[3]);
        float* padded = row_buf + kPad;
        for (int x = 0; x < roi; ++x) {
          padded[x] = wy[0] * r0[x] + wy[1] * r1[x] + wy[2] * r2[x] + wy[3] * r3[x];
        }
        for (int k = 1; k <= kPad; ++k)
          padded[-k] = padded[0], padded[roi - 1 + k] = padded[roi - 1];
        for (int u = 0; u < n; ++u) {
          const float* p = row_buf + taps.first[u];
          const std::array<float, 4>& wx = taps.weight[u];
          row[u] = wx[0] * p[0] + wx[1] * p[1] + wx[2] * p[2] + wx[3] * p[3];
        }
      }
      sum += lane_sum(row, n, [](float x) { return x; });
    }
    const double count = static_cast<double>(nn);
    const float mean = static_cast<float>(sum / count);
    double sq = 0;
    for (int v = 0; v < n; ++v) {
      sq += lane_sum(dst + static_cast<size_t>(v) * n, n,
                     [mean](float x) { return (x - mean) * (x - mean); });
    }
    const double var = sq / count;
    const float inv_std = var > kFlatVariance ? static_cast<float>(1.0 / std::sqrt(var)) : 0.0f;
    // Normalise + window, and the per-block sums of the centroid in the same pass.
    std::array<float, kCentroidBlocks * kCentroidBlocks> block_sum{}, block_sq{};
    int by = 0;
    for (int v = 0; v < n; ++v) {
      float* row = dst + static_cast<size_t>(v) * n;
      const float wy = window[v] * inv_std;
      for (int u = 0; u < n; ++u) row[u] = (row[u] - mean) * (wy * window[u]);
      if (v >= (by + 1) * n / kCentroidBlocks) ++by;
      for (int bx = 0; bx < kCentroidBlocks; ++bx) {
        const int u0 = bx * n / kCentroidBlocks, len = (bx + 1) * n / kCentroidBlocks - u0;
        const size_t b = static_cast<size_t>(by) * kCentroidBlocks + bx;
        block_sum[b] += static_cast<float>(lane_sum(row + u0, len, [](float x) { return x; }));
        block_sq[b] += static_cast<float>(lane_sum(row + u0, len, [](float x) { return x * x; }));
      }
    }
    return centroid(block_sum, block_sq);
  }

  // Centroid of the local contrast energy: the variance of each of kCentroidBlocks^2 blocks about
  // its own mean (so a step between net and water does not count), at the block centres.
  std::pair<float, float> centroid(
      const std::array<float, kCentroidBlocks * kCentroidBlocks>& block_sum,
      const std::array<float, kCentroidBlocks * kCentroidBlocks>& block_sq) const {
    const int n = shape.fft_size;
    double e = 0, eu = 0, ev = 0;
    for (int by = 0; by < kCentroidBlocks; ++by) {
      const int v0 = by * n / kCentroidBlocks, v1 = (by + 1) * n / kCentroidBlocks;
      for (int bx = 0; bx < kCentroidBlocks; ++bx) {
        const int u0 = bx * n / kCentroidBlocks, u1 = (bx + 1) * n / kCentroidBlocks;
        const size_t b = static_cast<size_t>(by) * kCentroidBlocks + bx;
        const float count = static_cast<float>((v1 - v0) * (u1 - u0));
        const double eb = std::max(0.0f, block_sq[b] - block_sum[b] * block_sum[b] / count);
        e += eb;
        eu += eb * 0.5 * (u0 + u1 - 1);
        ev += eb * 0.5 * (v0 + v1 - 1);
      }
    }
    if (!(e > 0)) return {0.0f, 0.0f};
    const double centre = 0.5 * (n - 1), scale = static_cast<double>(shape.roi_size) / n;
    return {static_cast<float>((eu / e - centre) * scale),
            static_cast<float>((ev / e - centre) * scale)};
  }

  template <class F>
  static double lane_sum(const float* x, int n, F f) {
    float lanes[8] = {};
    int i = 0;
    for (; i + 8 <= n; i += 8)
      for (int j = 0; j < 8; ++j) lanes[j] += f(x[i + j]);
    double total = 0;
    for (; i < n; ++i) total += f(x[i]);
    for (float l : lanes) total += l;
    return total;
  }

  std::span<const std::complex<float>> spectrum(int thread) const {
    return {reinterpret_cast<const std::complex<float>*>(out[thread].get()), nc};
  }
};

FftRoiCpu::FftRoiCpu(const FftRoiShape& shape, const PeakParams& params, int threads, bool measure)
    : impl_(std::make_unique<Impl>()) {
  validate(shape, false);
  if (threads < 1) throw Error("FftRoiCpu: threads must be >= 1, got " + std::to_string(threads));
  Impl& m = *impl_;
  m.shape = shape;
  m.params = params;
  m.threads = threads;
  const int n = shape.fft_size;
  m.nn = static_cast<size_t>(n) * n;
  m.nc = static_cast<size_t>(n) * (n / 2 + 1);
  m.taps = taps(shape.roi_size, n);
  for (int u = 0; u < n; ++u) {
    const double s = std::sin(3.14159265358979323846 * (u + 0.5) / n);
    m.window.push_back(shape.window ? static_cast<float>(s * s) : 1.0f);
  }
  for (int t = 0; t < threads; ++t) {
    m.in.push_back(fftw_array<float>(m.nn));
    m.out.push_back(fftw_array<fftwf_complex>(m.nc));
    m.rows.emplace_back(shape.roi_size + 2 * kPad);
  }
  std::lock_guard lock(planner_mutex());
  m.plan = fftwf_plan_dft_r2c_2d(n, n, m.in[0].get(), m.out[0].get(),
                                 measure ? FFTW_MEASURE : FFTW_ESTIMATE);
  if (!m.plan) throw Error("FftRoiCpu: FFTW could not plan a " + std::to_string(n) + "^2 r2c FFT");
}

FftRoiCpu::~FftRoiCpu() = default;
FftRoiCpu::FftRoiCpu(FftRoiCpu&&) noexcept = default;
FftRoiCpu& FftRoiCpu::operator=(FftRoiCpu&&) noexcept = default;

const FftRoiShape& FftRoiCpu::shape() const {
  return impl_->shape;
}
size_t FftRoiCpu::samples_per_roi() const {
  return impl_->nn;
}
size_t FftRoiCpu::spectrum_per_roi() const {
  return impl_->nc;
}

namespace {

void check_image(const FftRoiShape& s, const ImageU8& image, std::span<const RoiOrigin> rois) {
  if (image.width != s.width || image.height != s.height) {
    throw Error("fft_roi: image is " + std::to_string(image.width) + "x" +
                std::to_string(image.height) + ", the stage was built for " +
                std::to_string(s.width) + "x" + std::to_string(s.height));
  }
  validate(RoiNormalizeShape{s.width, s.height, 8, s.roi_size}, rois);
}

}  // namespace

void FftRoiCpu::prepare(const ImageU8& image, std::span<const RoiOrigin> rois,
                        std::span<float> samples) {
  Impl& m = *impl_;
  check_image(m.shape, image, rois);
  if (samples.size() < rois.size() * m.nn) {
    throw Error("FftRoiCpu::prepare: samples hold " + std::to_string(samples.size()) + " floats, " +
                std::to_string(rois.size() * m.nn) + " needed");
  }
  const int count = static_cast<int>(rois.size());
#pragma omp parallel for num_threads(m.threads) schedule(static)
  for (int r = 0; r < count; ++r) {
    m.prepare_one(image, rois[r], samples.data() + r * m.nn, m.rows[omp_get_thread_num()].data());
  }
}

void FftRoiCpu::transform(std::span<const float> samples, std::span<std::complex<float>> spectra) {
  Impl& m = *impl_;
  const size_t count = samples.size() / m.nn;
  if (samples.size() % m.nn != 0 || spectra.size() < count * m.nc) {
    throw Error("FftRoiCpu::transform: " + std::to_string(samples.size()) + " samples and " +
                std::to_string(spectra.size()) + " bins do not make whole ROIs of " +
                std::to_string(m.nn) + " samples / " + std::to_string(m.nc) + " bins");
  }
  const int n = static_cast<int>(count);
#pragma omp parallel for num_threads(m.threads) schedule(static)
  for (int r = 0; r < n; ++r) {
    // Through the aligned scratch: the caller's arrays need not have FFTW's SIMD alignment.
    float* in = m.in[omp_get_thread_num()].get();
    fftwf_complex* out = m.out[omp_get_thread_num()].get();
    std::copy_n(samples.data() + r * m.nn, m.nn, in);
    fftwf_execute_dft_r2c(m.plan, in, out);
    std::copy_n(reinterpret_cast<const std::complex<float>*>(out), m.nc, spectra.data() + r * m.nc);
  }
}

std::vector<RoiLattice> FftRoiCpu::run(const ImageU8& image, std::span<const RoiOrigin> rois) {
  Impl& m = *impl_;
  check_image(m.shape, image, rois);
  std::vector<RoiLattice> lattices(rois.size());
  const int count = static_cast<int>(rois.size());
#pragma omp parallel for num_threads(m.threads) schedule(dynamic)
  for (int r = 0; r < count; ++r) {
    const int t = omp_get_thread_num();
    const auto [dx, dy] = m.prepare_one(image, rois[r], m.in[t].get(), m.rows[t].data());
    fftwf_execute_dft_r2c(m.plan, m.in[t].get(), m.out[t].get());
    lattices[r] = analyze_spectrum(m.spectrum(t), m.shape, m.params);
    lattices[r].centroid_dx = dx;
    lattices[r].centroid_dy = dy;
  }
  return lattices;
}

}  // namespace pensight::kernels
