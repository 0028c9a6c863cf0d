#include <fftw3.h>
#include <omp.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <mutex>
#include <numbers>
#include <string>

#include "core/error.h"
#include "core/file_bytes.h"
#include "kernels/fft_roi/fft_roi.h"
#include "runtime/cache_dir.h"
#include "runtime/simd_clones.h"

namespace pensight::kernels {
namespace {

// FFTW's planner is not thread-safe; execution of a finished plan is.
std::mutex& planner_mutex() {
  static std::mutex m;
  return m;
}

// FFTW_PATIENT found a 256^2 r2c plan up to ~20 % faster than FFTW_MEASURE's on the CI machine
// (docs/performance.md) but searches for ~2 s. Its wisdom stays in the process, and in the cache
// directory (runtime/cache_dir.h) for the next process. Call with planner_mutex() held.
fftwf_plan patient_plan(int n, float* in, fftwf_complex* out) {
  static bool imported = false;
  const std::filesystem::path dir = cache_dir();
  const std::filesystem::path file =
      dir.empty() || dir == "-" ? std::filesystem::path() : dir / "fftw3f.wisdom";
  if (!imported && !file.empty()) {
    const std::string wisdom = read_file_bytes(file).value_or("");  // missing: a cache miss
    if (!wisdom.empty()) fftwf_import_wisdom_from_string(wisdom.c_str());
  }
  imported = true;
  if (fftwf_plan p = fftwf_plan_dft_r2c_2d(n, n, in, out, FFTW_PATIENT | FFTW_WISDOM_ONLY)) {
    return p;
  }
  fftwf_plan p = fftwf_plan_dft_r2c_2d(n, n, in, out, FFTW_PATIENT);
  if (p && !file.empty()) {
    std::unique_ptr<char, decltype(&std::free)> wisdom(fftwf_export_wisdom_to_string(), &std::free);
    if (wisdom) write_cache_file(file, wisdom.get());
  }
  return p;
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

// Resampling of a line of `roi` pixels to n samples, sample u at x = (u + 0.5) * roi / n - 0.5: a
// [1 2 1]/4 binomial prefilter convolved with linear interpolation, i.e. four source taps floor(x)
// - 1 .. floor(x) + 2 with weights ((1 - f), (2 - f), (1 + f), f) / 4, clamped to the ROI (the
// form shaders/fft_roi/extract.comp uses). Plain bilinear lets the spectral image of a lattice
// near the pixel Nyquist (300 - f cycles per ROI) through, which the decimation to 256 folds into
// the band as a false, coarser lattice; the binomial zero at 0.5 cycles/px removes it.
// Rows use the four taps; columns split them into the prefilter (one contiguous pass) and a
// two-tap interpolation between prefiltered pixels floor(x) and floor(x) + 1, the same sum.
struct RowTaps {
  std::array<int, 4> index;  // clamped source rows
  std::array<float, 4> weight;
};
// Edge replication on each side of a line, so that the taps of every sample are in range.
constexpr int kPad = 2;

std::vector<RowTaps> row_taps(int roi, int n) {
  std::vector<RowTaps> taps;
  const double scale = static_cast<double>(roi) / n;
  for (int v = 0; v < n; ++v) {
    if (roi == n) {  // no resampling: the pixels themselves
      taps.push_back({{v, v, v, v}, {1, 0, 0, 0}});
      continue;
    }
    const double y = (v + 0.5) * scale - 0.5;
    const int i = static_cast<int>(std::floor(y));
    const auto f = static_cast<float>(y - i);
    RowTaps t;
    for (int j = 0; j < 4; ++j) t.index[j] = std::clamp(i - 1 + j, 0, roi - 1);
    t.weight = {(1 - f) / 4, (2 - f) / 4, (1 + f) / 4, f / 4};
    taps.push_back(t);
  }
  return taps;
}

template <class F>
double lane_sum(const float* x, int n, F f) {
  float lanes[8] = {};
  int i = 0;
  for (; i + 8 <= n; i += 8)
    for (int j = 0; j < 8; ++j) lanes[j] += f(x[i + j]);
  double total = 0;
  for (; i < n; ++i) total += f(x[i]);
  for (float l : lanes) total += l;
  return total;
}

}  // namespace

// Must match the 16 x 16 blocks of shaders/fft_roi/extract.comp (one per invocation).
constexpr int kCentroidBlocks = 16;

// The stage per call, one task per distinct ROI x origin ("column"; 6 in the default grid, spread
// over the threads): (1) every image row the column's ROIs cover is resampled horizontally once
// (the 5 ROI rows of the default grid overlap, so each image row serves up to 5 ROIs); (2) per
// ROI of the column, the vertical taps blend four of those rows into each sample row, then
// normalisation, window and the centroid's block sums in one more pass; FFT; peaks. Tasks share
// nothing, so no thread waits for another before the end.
struct FftRoiCpu::Impl {
  FftRoiShape shape;
  PeakParams params;
  int threads;
  size_t nn, nc;
  bool prefilter;             // false when fft_size == roi_size_px: samples are the pixels
  std::vector<int> lerp_at;   // per column u: prefiltered pixel floor(x), index into a padded line
  std::vector<float> lerp_f;  // its interpolation fraction
  std::vector<RowTaps> rows;
  std::vector<float> window;
  fftwf_plan plan = nullptr;

  // The current call's columns: ROIs order[first .. first + count) have x origin x0 and need
  // image rows [y_begin, y_end). Kept between calls (no allocation per frame).
  struct Column {
    int x0, y_begin, y_end, first, count;
  };
  std::vector<Column> columns;
  std::vector<int> roi_column, order;

  // Per-thread scratch: one ROI of samples and its spectrum, a padded line, block sums, and the
  // column's resampled image rows (row y at y * n).
  struct Scratch {
    FftwArray<float> in;
    FftwArray<fftwf_complex> out;
    std::vector<float> line;             // roi + 2 * kPad pixels, then its prefiltered values
    std::vector<float> col_sum, col_sq;  // per column, over the rows of one block row
    std::vector<float> resampled;
  };
  std::vector<Scratch> scratch;

  ~Impl() {
    if (plan) {
      std::lock_guard lock(planner_mutex());
      fftwf_destroy_plan(plan);
    }
  }

  void plan_columns(std::span<const RoiOrigin> rois) {
    columns.clear();
    roi_column.clear();
    for (const RoiOrigin& o : rois) {
      auto it = std::find_if(columns.begin(), columns.end(),
                             [&](const Column& c) { return c.x0 == o.x; });
      if (it == columns.end()) {
        columns.push_back({o.x, o.y, o.y + shape.roi_size_px, 0, 0});
        it = columns.end() - 1;
      }
      it->y_begin = std::min(it->y_begin, o.y);
      it->y_end = std::max(it->y_end, o.y + shape.roi_size_px);
      ++it->count;
      roi_column.push_back(static_cast<int>(it - columns.begin()));
    }
    int first = 0;
    for (Column& c : columns) c.first = first, first += c.count, c.count = 0;
    order.resize(rois.size());
    for (size_t r = 0; r < rois.size(); ++r) {
      Column& c = columns[roi_column[r]];
      order[c.first + c.count++] = static_cast<int>(r);
    }
  }

  // Step (1) for one column into the thread's scratch.
  void resample_column(const ImageU8& image, const Column& c, Scratch& s) const {
    const size_t n = static_cast<size_t>(shape.fft_size);
    for (int y = c.y_begin; y < c.y_end; ++y) {
      resample_line(&image.at(c.x0, y), s.resampled.data() + y * n, s.line.data());
    }
  }

  // Runs f(roi index, scratch) for every ROI, after its column's rows are resampled.
  template <class F>
  void for_each_roi(const ImageU8& image, std::span<const RoiOrigin> rois, F f) {
    plan_columns(rois);
    const int count = static_cast<int>(columns.size());
#pragma omp parallel for num_threads(threads) schedule(dynamic)
    for (int c = 0; c < count; ++c) {
      Scratch& s = scratch[omp_get_thread_num()];
      resample_column(image, columns[c], s);
      for (int i = 0; i < columns[c].count; ++i) f(order[columns[c].first + i], s);
    }
  }

  PENSIGHT_SIMD_CLONES void resample_line(const uint8_t* __restrict src, float* __restrict dst,
                                          float* __restrict line) const {
    const int n = shape.fft_size, roi = shape.roi_size_px;
    if (!prefilter) {
      for (int u = 0; u < n; ++u) dst[u] = src[u];
      return;
    }
    // Padded line p[-kPad .. roi - 1 + kPad] at line[0 ..], prefiltered in place one step left:
    // line[k] becomes the prefiltered pixel k - kPad + 1, for k = 0 .. roi + 1.
    float* p = line + kPad;
    for (int x = 0; x < roi; ++x) p[x] = src[x];
    for (int k = 1; k <= kPad; ++k) p[-k] = p[0], p[roi - 1 + k] = p[roi - 1];
    for (int k = 0; k < roi + 2; ++k)
      line[k] = 0.25f * (line[k] + line[k + 2]) + 0.5f * line[k + 1];
    for (int u = 0; u < n; ++u) {
      const float a = line[lerp_at[u]], b = line[lerp_at[u] + 1];
      dst[u] = a + lerp_f[u] * (b - a);
    }
  }

  // Step (2) into dst (n^2 floats): vertical taps, zero mean / unit variance, window.
  // Returns the energy centroid of the result, in image pixels from the ROI centre.
  PENSIGHT_SIMD_CLONES std::pair<float, float> finish_roi(RoiOrigin o, float* __restrict dst,
                                                          Scratch& s) const {
    const int n = shape.fft_size;
    auto resampled_row = [&](int y) { return s.resampled.data() + static_cast<size_t>(y) * n; };
    // Sums about a pivot inside the data range: the variance does not cancel against the mean.
    const float pivot = resampled_row(o.y + rows[0].index[0])[0];
    double sum = 0, sq = 0;
    for (int v = 0; v < n; ++v) {
      const RowTaps& t = rows[v];
      const float* __restrict r0 = resampled_row(o.y + t.index[0]);
      const float* __restrict r1 = resampled_row(o.y + t.index[1]);
      const float* __restrict r2 = resampled_row(o.y + t.index[2]);
      const float* __restrict r3 = resampled_row(o.y + t.index[3]);
      float* __restrict row = dst + static_cast<size_t>(v) * n;
      const float w0 = t.weight[0], w1 = t.weight[1], w2 = t.weight[2], w3 = t.weight[3];
      for (int u = 0; u < n; ++u) row[u] = w0 * r0[u] + w1 * r1[u] + w2 * r2[u] + w3 * r3[u];
      sum += lane_sum(row, n, [pivot](float x) { return x - pivot; });
      sq += lane_sum(row, n, [pivot](float x) { return (x - pivot) * (x - pivot); });
    }
    const double count = static_cast<double>(nn);
    const double shift = sum / count;
    const float mean = static_cast<float>(pivot + shift);
    const double var = sq / count - shift * shift;
    const float inv_std = var > kFlatVariance ? static_cast<float>(1.0 / std::sqrt(var)) : 0.0f;
    // Normalise + window, with per-column sums over each block row for the centroid.
    std::array<float, kCentroidBlocks * kCentroidBlocks> block_sum{}, block_sq{};
    float* __restrict cs = s.col_sum.data();
    float* __restrict cq = s.col_sq.data();
    const float* __restrict w = window.data();
    for (int by = 0; by < kCentroidBlocks; ++by) {
      std::fill_n(cs, n, 0.0f);
      std::fill_n(cq, n, 0.0f);
      for (int v = by * n / kCentroidBlocks; v < (by + 1) * n / kCentroidBlocks; ++v) {
        float* __restrict row = dst + static_cast<size_t>(v) * n;
        const float wy = w[v] * inv_std;
        for (int u = 0; u < n; ++u) {
          const float x = (row[u] - mean) * (wy * w[u]);
          row[u] = x;
          cs[u] += x;
          cq[u] += x * x;
        }
      }
      for (int bx = 0; bx < kCentroidBlocks; ++bx) {
        const int u0 = bx * n / kCentroidBlocks, len = (bx + 1) * n / kCentroidBlocks - u0;
        const size_t b = static_cast<size_t>(by) * kCentroidBlocks + bx;
        block_sum[b] = static_cast<float>(lane_sum(cs + u0, len, [](float x) { return x; }));
        block_sq[b] = static_cast<float>(lane_sum(cq + u0, len, [](float x) { return x; }));
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
    const double centre = 0.5 * (n - 1), scale = static_cast<double>(shape.roi_size_px) / n;
    return {static_cast<float>((eu / e - centre) * scale),
            static_cast<float>((ev / e - centre) * scale)};
  }

  std::span<const std::complex<float>> spectrum(const Scratch& s) const {
    return {reinterpret_cast<const std::complex<float>*>(s.out.get()), nc};
  }
};

FftRoiCpu::FftRoiCpu(const FftRoiShape& shape, const PeakParams& params, int threads,
                     FftPlanning planning)
    : impl_(std::make_unique<Impl>()) {
  validate(shape, FftSizes::kAny);
  if (threads < 1) throw Error("FftRoiCpu: threads must be >= 1, got " + std::to_string(threads));
  Impl& m = *impl_;
  m.shape = shape;
  m.params = params;
  m.threads = threads;
  const int n = shape.fft_size, roi = shape.roi_size_px;
  m.nn = static_cast<size_t>(n) * n;
  m.nc = static_cast<size_t>(n) * (n / 2 + 1);
  m.prefilter = n != roi;
  m.rows = row_taps(roi, n);
  const double scale = static_cast<double>(roi) / n;
  for (int u = 0; u < n; ++u) {
    // Prefiltered pixel k sits at line[k + kPad - 1] (see resample_line).
    const double x = (u + 0.5) * scale - 0.5;
    const int i = static_cast<int>(std::floor(x));
    m.lerp_at.push_back(i + kPad - 1);
    m.lerp_f.push_back(static_cast<float>(x - i));
    const double s = std::sin(std::numbers::pi * (u + 0.5) / n);
    m.window.push_back(shape.window ? static_cast<float>(s * s) : 1.0f);
  }
  for (int t = 0; t < threads; ++t) {
    m.scratch.push_back({fftw_array<float>(m.nn), fftw_array<fftwf_complex>(m.nc),
                         std::vector<float>(roi + 2 * kPad), std::vector<float>(n),
                         std::vector<float>(n),
                         std::vector<float>(static_cast<size_t>(shape.height) * n)});
  }
  std::lock_guard lock(planner_mutex());
  m.plan = planning == FftPlanning::kPatient
               ? patient_plan(n, m.scratch[0].in.get(), m.scratch[0].out.get())
               : fftwf_plan_dft_r2c_2d(n, n, m.scratch[0].in.get(), m.scratch[0].out.get(),
                                       FFTW_ESTIMATE);
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
  validate(s, rois);
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
  m.for_each_roi(image, rois, [&](int r, Impl::Scratch& s) {
    m.finish_roi(rois[r], samples.data() + r * m.nn, s);
  });
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
    Impl::Scratch& s = m.scratch[omp_get_thread_num()];
    std::copy_n(samples.data() + r * m.nn, m.nn, s.in.get());
    fftwf_execute_dft_r2c(m.plan, s.in.get(), s.out.get());
    std::copy_n(m.spectrum(s).data(), m.nc, spectra.data() + r * m.nc);
  }
}

std::vector<RoiLattice> FftRoiCpu::run(const ImageU8& image, std::span<const RoiOrigin> rois) {
  Impl& m = *impl_;
  check_image(m.shape, image, rois);
  std::vector<RoiLattice> lattices(rois.size());
  m.for_each_roi(image, rois, [&](int r, Impl::Scratch& s) {
    const auto [dx, dy] = m.finish_roi(rois[r], s.in.get(), s);
    fftwf_execute_dft_r2c(m.plan, s.in.get(), s.out.get());
    lattices[r] = analyze_spectrum(m.spectrum(s), m.shape, m.params);
    lattices[r].centroid_dx = dx;
    lattices[r].centroid_dy = dy;
  });
  return lattices;
}

}  // namespace pensight::kernels
