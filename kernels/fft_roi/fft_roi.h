#pragma once
// FFT net detection per ROI: a grid of square ROIs is cut from a grey frame, each ROI resampled
// to a power-of-two square (bilinear after a [1 2 1] binomial anti-alias prefilter), normalised to
// zero mean / unit variance, multiplied by a separable Hann window, transformed with a
// real-to-complex 2D FFT, and its power spectrum searched for the two base frequency vectors of the
// net lattice (sub-bin refined). Only the small per-ROI RoiLattice records leave the device.
//
// Spectrum layout (all backends, as FFTW's r2c): per ROI fft_size rows (ky, natural order with
// negative frequencies in the upper half) of fft_size/2+1 complex bins (kx >= 0), row-major.
// A bin index k is k cycles per ROI, whatever fft_size is, so frequencies in image pixels are
// k / roi_size_px cycles per pixel.
#include <complex>
#include <cstdint>
#include <memory>
#include <span>
#include <vector>

#include "core/default_camera.h"
#include "core/image.h"
#include "runtime/vk_buffer.h"
#include "runtime/vk_pipeline.h"
#include "runtime/vk_stream.h"

namespace pensight::kernels {

struct RoiOrigin {
  int32_t x = 0;  // top-left pixel of the ROI
  int32_t y = 0;
};

// A flat ROI (variance below this, in grey levels^2) normalises to all zeros: no lattice, and no
// division by a near-zero standard deviation. The shaders and CUDA use the same threshold.
inline constexpr double kFlatVariance = 1e-9;

// The default ROI side: 6 ROIs span the default 720 px width, 5 the 540 px height (overlapping).
inline constexpr int kDefaultRoiSize_px = 300;
// The smallest ROI and FFT side: below, a ROI holds too few cells for a lattice peak.
inline constexpr int kMinRoiSize_px = 16, kMinFftSize = 16;

// rows x cols ROIs of roi_size_px; top-left corners spread evenly from border_px to the far edge
// (the last column ends at width - 1, the last row at height - 1).
struct RoiGrid {
  int rows = 5;
  int cols = 6;
  int roi_size_px = kDefaultRoiSize_px;
  int border_px = 0;
};

// Row-major top-left corners; throws pensight::Error naming the parameter when the grid does not
// fit the image.
std::vector<RoiOrigin> roi_grid(int width, int height, const RoiGrid& grid);

struct FftRoiShape {
  int width = kDefaultImageWidth_px;
  int height = kDefaultImageHeight_px;
  int roi_size_px = kDefaultRoiSize_px;  // ROI side in image pixels
  int fft_size = 256;  // resampled side; a power of two for the Vulkan and CUDA paths
  bool window = true;  // separable Hann window (off = the published method)
};

// Peak search over the power spectrum. Frequencies are in cycles per ROI (= FFT bins).
struct PeakParams {
  // Fewer lattice periods across the ROI cannot be told from illumination gradients and window
  // leakage (open water gave false 0.1 m nets at 3); 5 limits the near range to ~0.23 m at the
  // default 300 px ROI, fx 462 px and 30 mm mesh.
  float min_cycles = 5.0f;
  float max_nyquist_share = 0.9f;  // above max_nyquist_share * fft_size / 2: resampling alias
  // A bin between the band and the Nyquist circle stronger than this times the strongest in-band
  // bin: the lattice is finer than the band, and what the band holds is an alias (the twines'
  // second harmonic folded by the camera's own sampling to 300 - 2f cycles read a 5.4 m net as
  // 3.3 m). The ROI then has no lattice.
  float beyond_band_ratio = 1.0f;
  float min_angle_deg = 25.0f;  // the second base vector makes at least this angle with the first
  float subharmonic_ratio = 0.2f;  // a peak at half the frequency this strong is the fundamental
  // A local maximum below the band at half the lattice's frequency (to the bin), at least
  // kMinCoarseCycles from DC (the Hann window's DC lobe spans 2 bins), stronger than this times the
  // lattice peak: the net is coarser than the band and the band holds its second harmonic (a
  // 41 mm mesh at 0.25 m, 3.9 cycles, read at 7.8 cycles as 0.5 m). The ROI then has no lattice.
  // Rendered coarse nets give 0.8-1.6; fouling and light on the real frame (its net at 5.5
  // cycles) give up to 0.35. Nets under 2.5 cycles, whose third harmonic can be the strongest in
  // the band, are beyond the detector's near range (0.12 m for a 30 mm mesh at fx 462 px).
  float below_band_ratio = 0.5f;
  bool subbin = true;  // log-parabolic sub-bin refinement (off = integer bins)
};

// Lowest frequency, in cycles per ROI, that the below-band rule looks at.
inline constexpr int kMinCoarseCycles = 2;
// A bin at half a peak's frequency is taken as its fundamental only where it is at least
// kRidgeProminence times the strongest bin kRidgeOffset0/1 bins (along its larger axis) further out
// and nearer in on its line through DC, beyond the Hann main lobe (2 bins). A rope's ridge through
// DC is stronger nearer DC, and two ropes' fringes put bins as strong 4-5 bins away. A real net's
// fundamental is broad: at 2 x, the fouled net of ../shared/real/solaqua_far lost its pose and on
// rendered ropes 117 -> 120 of 121 frames had one (docs/validation-log.md).
inline constexpr float kRidgeProminence = 1.0f;
inline constexpr int kRidgeOffset0 = 4, kRidgeOffset1 = 5;

// Per-ROI result (plain floats: the layout of the Vulkan and CUDA result buffers).
struct RoiLattice {
  float f1x = 0, f1y = 0;  // base frequency vectors in cycles per image pixel, half plane f.x >= 0,
  float f2x = 0, f2y = 0;  // ordered by angle atan2(f.y, f.x) ascending
  float quality = 0;       // share of the ROI's in-band spectral energy in the two peaks (0..1)
  float contrast = 0;      // weaker peak's power over the mean in-band power
  // Centroid of the windowed ROI's local contrast energy (16 x 16 blocks, each block's variance
  // about its own mean), in image pixels from the ROI centre: where the lattice was measured. A
  // ROI half on the net measures the lattice of that half.
  float centroid_dx = 0, centroid_dy = 0;
};
static_assert(sizeof(RoiLattice) == 8 * sizeof(float));

// Which FFT sizes a backend can run: the CPU's FFTW any, the shaders' radix-2 stages powers of 2.
enum class FftSizes { kAny, kPowerOfTwo };
void validate(const FftRoiShape& shape, FftSizes sizes);
// Throws pensight::Error naming the ROI when one leaves the shape's image.
void validate(const FftRoiShape& shape, std::span<const RoiOrigin> rois);

// Sub-bin offset of a spectral peak from the powers at -1, 0, +1 bins: the vertex of the parabola
// through their logs (exact for a Gaussian peak; close to the Hann main lobe), within +-0.5; 0
// where the three are not a maximum. The shaders and CUDA mirror it.
float peak_vertex(float power_minus, float power_centre, float power_plus);

// Analyses one ROI's r2c spectrum (layout above). Used by the CPU path; the shaders mirror it.
RoiLattice analyze_spectrum(std::span<const std::complex<float>> spectrum, const FftRoiShape& shape,
                            const PeakParams& params);

// How FftRoiCpu plans its FFT: kPatient searches for the fastest plan (FFTW_PATIENT), kQuick
// takes FFTW's estimate at once (tests and benchmarks of something else).
enum class FftPlanning { kPatient, kQuick };

// CPU reference on FFTW: planned once per shape (FFTW_PATIENT unless kQuick: ~2 s the
// first time on a machine, then read from the FFTW wisdom in runtime/cache_dir.h's directory),
// the ROIs' columns (distinct x origins) spread over `threads` OpenMP threads. Not thread-safe
// itself (owns its work buffers).
class FftRoiCpu {
 public:
  FftRoiCpu(const FftRoiShape& shape, const PeakParams& params = {}, int threads = 1,
            FftPlanning planning = FftPlanning::kPatient);
  ~FftRoiCpu();
  FftRoiCpu(FftRoiCpu&&) noexcept;
  FftRoiCpu& operator=(FftRoiCpu&&) noexcept;

  const FftRoiShape& shape() const;
  size_t samples_per_roi() const;   // fft_size^2 floats
  size_t spectrum_per_roi() const;  // fft_size * (fft_size / 2 + 1) complex bins

  // The whole stage: ROIs -> one RoiLattice each.
  std::vector<RoiLattice> run(const ImageU8& image, std::span<const RoiOrigin> rois);
  // Stage pieces, for tests and benchmarks. samples: rois * samples_per_roi() floats.
  void prepare(const ImageU8& image, std::span<const RoiOrigin> rois, std::span<float> samples);
  // spectra: rois * spectrum_per_roi() bins.
  void transform(std::span<const float> samples, std::span<std::complex<float>> spectra);

  struct Impl;

 private:
  std::unique_ptr<Impl> impl_;
};

// Vulkan: extract (resample + normalise + window), row FFT (two real rows per complex FFT),
// column FFT, spectrum analysis; four dispatches recorded once, data kept on the device.
class FftRoiVk {
 public:
  FftRoiVk(const vk::Context& ctx, const FftRoiShape& shape, const PeakParams& params = {});

  const FftRoiShape& shape() const { return shape_; }
  size_t image_bytes() const;  // packed 8-bit frame, padded to whole words
  size_t samples_bytes(uint32_t num_rois) const;
  size_t spectrum_bytes(uint32_t num_rois) const;

  // image: packed u8 pixels; rois: RoiOrigin[num_rois]; samples / spectrum: scratch of the sizes
  // above; lattices: RoiLattice[num_rois].
  void record(vk::CommandStream& stream, const vk::Buffer& image, const vk::Buffer& rois,
              const vk::Buffer& samples, const vk::Buffer& spectrum, const vk::Buffer& lattices,
              uint32_t num_rois) const;
  // Only the two FFT passes (samples -> spectrum), for tests against FFTW.
  void record_fft(vk::CommandStream& stream, const vk::Buffer& samples, const vk::Buffer& spectrum,
                  uint32_t num_rois) const;

  // One-off convenience (allocates buffers on each call).
  std::vector<RoiLattice> run(const ImageU8& image, std::span<const RoiOrigin> rois) const;

 private:
  const vk::Context* ctx_;
  FftRoiShape shape_;
  // Borrowed from the context's registry: every FftRoiVk of one shape shares them.
  const vk::Pipeline* extract_;
  const vk::Pipeline* rows_;
  const vk::Pipeline* cols_;
  const vk::Pipeline* peaks_;
};

#if PENSIGHT_HAS_CUDA
// CUDA: the same stage with cuFFT (batched r2c plan made once per shape).
class FftRoiCuda {
 public:
  FftRoiCuda(const FftRoiShape& shape, const PeakParams& params, int max_rois);
  ~FftRoiCuda();
  FftRoiCuda(FftRoiCuda&&) noexcept;
  FftRoiCuda& operator=(FftRoiCuda&&) noexcept;
  std::vector<RoiLattice> run(const ImageU8& image, std::span<const RoiOrigin> rois);

  struct Impl;

 private:
  std::unique_ptr<Impl> impl_;
};
#endif

}  // namespace pensight::kernels
