#include <bit>
#include <cmath>
#include <string>

#include "core/error.h"
#include "core/units.h"
#include "kernels/fft_roi/fft_roi.h"
#include "kernels/kernel_shader.h"

namespace pensight::kernels {
namespace {

struct FftRoiPush {
  uint32_t num_rois;
};

uint32_t u32(int v) {
  return static_cast<uint32_t>(v);
}
uint32_t bits(float v) {
  return std::bit_cast<uint32_t>(v);
}

const FftRoiShape& checked(const FftRoiShape& shape) {
  validate(shape, FftSizes::kPowerOfTwo);
  return shape;
}

std::vector<uint32_t> peak_constants(const FftRoiShape& s, const PeakParams& p) {
  const float r_max = p.max_nyquist_share * static_cast<float>(s.fft_size / 2);
  const float c = std::cos(static_cast<float>(deg_to_rad(p.min_angle_deg)));
  return {u32(s.fft_size),
          u32(s.roi_size_px),
          bits(p.min_cycles * p.min_cycles),
          bits(r_max * r_max),
          bits(c * c),
          bits(p.subharmonic_ratio),
          p.subbin ? 1u : 0u,
          bits(p.beyond_band_ratio),
          bits(p.below_band_ratio),
          u32(kMinCoarseCycles * kMinCoarseCycles),
          u32(kMinCoarseCycles),
          bits(kRidgeProminence),
          u32(kRidgeOffset0),
          u32(kRidgeOffset1)};
}

}  // namespace

FftRoiVk::FftRoiVk(const vk::Context& ctx, const FftRoiShape& shape, const PeakParams& params)
    : ctx_(&ctx),
      shape_(checked(shape)),
      extract_(&ctx.pipeline({.shader = kernel_shader("fft_roi/extract"),
                              .num_buffers = 4,
                              .push_constant_bytes = sizeof(FftRoiPush),
                              .specialization = {u32(shape.width), u32(shape.roi_size_px),
                                                 u32(shape.fft_size), shape.window ? 1u : 0u}})),
      rows_(&ctx.pipeline({.shader = kernel_shader("fft_roi/fft_rows"),
                           .num_buffers = 2,
                           .push_constant_bytes = sizeof(FftRoiPush),
                           .specialization = {u32(shape.fft_size), u32(shape.fft_size / 2)}})),
      cols_(&ctx.pipeline({.shader = kernel_shader("fft_roi/fft_cols"),
                           .num_buffers = 1,
                           .push_constant_bytes = sizeof(FftRoiPush),
                           .specialization = {u32(shape.fft_size), u32(shape.fft_size / 2)}})),
      peaks_(&ctx.pipeline({.shader = kernel_shader("fft_roi/peaks"),
                            .num_buffers = 2,
                            .push_constant_bytes = sizeof(FftRoiPush),
                            .specialization = peak_constants(shape, params)})) {}

size_t FftRoiVk::image_bytes() const {
  return (static_cast<size_t>(shape_.width) * shape_.height + 3) / 4 * 4;
}

size_t FftRoiVk::samples_bytes(uint32_t num_rois) const {
  return static_cast<size_t>(num_rois) * shape_.fft_size * shape_.fft_size * sizeof(float);
}

size_t FftRoiVk::spectrum_bytes(uint32_t num_rois) const {
  return static_cast<size_t>(num_rois) * shape_.fft_size * (shape_.fft_size / 2 + 1) * 2 *
         sizeof(float);
}

void FftRoiVk::record_fft(vk::CommandStream& stream, const vk::Buffer& samples,
                          const vk::Buffer& spectrum, uint32_t num_rois) const {
  if (samples.size_bytes() < samples_bytes(num_rois) ||
      spectrum.size_bytes() < spectrum_bytes(num_rois)) {
    throw Error("FftRoiVk::record_fft: the samples or spectrum buffer is smaller than " +
                std::to_string(num_rois) + " ROIs need");
  }
  const uint32_t half = u32(shape_.fft_size / 2);
  stream.dispatch(*rows_, {vk::in(samples), vk::out(spectrum)}, {half, num_rois, 1},
                  FftRoiPush{num_rois}, "fft_rows");
  stream.dispatch(*cols_, {vk::inout(spectrum)}, {half + 1, num_rois, 1}, FftRoiPush{num_rois},
                  "fft_cols");
}

void FftRoiVk::record(vk::CommandStream& stream, const vk::Buffer& image, const vk::Buffer& rois,
                      const vk::Buffer& samples, const vk::Buffer& spectrum,
                      const vk::Buffer& lattices, uint32_t num_rois) const {
  if (image.size_bytes() < image_bytes() || rois.size_bytes() < num_rois * sizeof(RoiOrigin) ||
      lattices.size_bytes() < num_rois * sizeof(RoiLattice)) {
    throw Error(
        "FftRoiVk::record: the image, ROI or lattice buffer is smaller than the shape and " +
        std::to_string(num_rois) + " ROIs need");
  }
  stream.dispatch(*extract_, {vk::in(image), vk::in(rois), vk::out(samples), vk::out(lattices)},
                  {num_rois, 1, 1}, FftRoiPush{num_rois}, "fft_extract");
  record_fft(stream, samples, spectrum, num_rois);
  stream.dispatch(*peaks_, {vk::in(spectrum), vk::out(lattices)}, {num_rois, 1, 1},
                  FftRoiPush{num_rois}, "fft_peaks");
}

std::vector<RoiLattice> FftRoiVk::run(const ImageU8& image, std::span<const RoiOrigin> rois) const {
  if (image.width != shape_.width || image.height != shape_.height) {
    throw Error("FftRoiVk::run: image is " + std::to_string(image.width) + "x" +
                std::to_string(image.height) + ", the stage was built for " +
                std::to_string(shape_.width) + "x" + std::to_string(shape_.height));
  }
  validate(shape_, rois);
  if (rois.empty()) return {};
  const auto n = static_cast<uint32_t>(rois.size());
  vk::Buffer image_buf(*ctx_, image_bytes());
  image_buf.upload(image.pixels.data(), image.pixels.size());
  vk::Buffer roi_buf(*ctx_, rois.size_bytes());
  roi_buf.upload(rois.data(), rois.size_bytes());
  vk::Buffer samples(*ctx_, samples_bytes(n));
  vk::Buffer spectrum(*ctx_, spectrum_bytes(n));
  vk::TypedBuffer<RoiLattice> lattices(*ctx_, rois.size(), vk::MemoryUsage::kReadback);
  vk::CommandStream stream(*ctx_);
  record(stream, image_buf, roi_buf, samples, spectrum, lattices.raw(), n);
  stream.submit_and_wait();
  return lattices.to_vector();
}

}  // namespace pensight::kernels
