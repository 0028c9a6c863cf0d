#pragma once
// ROI extraction and normalisation: square ROIs cut from a grey image (8- or 16-bit), each
// scaled to zero mean and unit standard deviation, as the FFT net detector consumes them.
// Output layout: ROI-major, then row-major within the ROI: out[(r * size + y) * size + x].
// A flat ROI (variance < kFlatVariance grey levels^2) becomes all zeros.
#include <cstdint>
#include <span>
#include <vector>

#include "runtime/image.h"
#include "runtime/vk_pipeline.h"
#include "runtime/vk_stream.h"

namespace pensight::kernels {

struct RoiOrigin {
  int32_t x = 0;  // top-left pixel of the ROI
  int32_t y = 0;
};

inline constexpr double kFlatVariance = 1e-9;

struct RoiNormalizeShape {
  int width = 720;
  int height = 540;
  int bits = 8;  // 8 or 16
  int roi_size = 300;
};

// Throws pensight::Error naming the problem when the shape is unusable or an ROI leaves the image.
void validate(const RoiNormalizeShape& shape, std::span<const RoiOrigin> rois);

// CPU reference (double accumulation). `out` must hold rois.size() * roi_size^2 floats.
void roi_normalize_cpu(const ImageU8& image, std::span<const RoiOrigin> rois, int roi_size,
                       std::span<float> out);
void roi_normalize_cpu(const ImageU16& image, std::span<const RoiOrigin> rois, int roi_size,
                       std::span<float> out);

// Vulkan implementation: one workgroup per ROI. Build once per shape, record into any stream.
class RoiNormalizeVk {
 public:
  RoiNormalizeVk(const vk::Context& ctx, const RoiNormalizeShape& shape);

  const RoiNormalizeShape& shape() const { return shape_; }
  // Bytes of the packed image buffer (pixels as stored, padded to whole 32-bit words).
  size_t image_bytes() const;
  // image: packed pixels; rois: RoiOrigin[num_rois]; out: float[num_rois * roi_size^2].
  void record(vk::CommandStream& stream, const vk::Buffer& image, const vk::Buffer& rois,
              const vk::Buffer& out, uint32_t num_rois) const;

  // One-off convenience (allocates buffers on each call): upload, run, download.
  std::vector<float> run(const ImageU8& image, std::span<const RoiOrigin> rois) const;
  std::vector<float> run(const ImageU16& image, std::span<const RoiOrigin> rois) const;

 private:
  template <class Pixel>
  std::vector<float> run_impl(const Image<Pixel>& image, std::span<const RoiOrigin> rois) const;

  const vk::Context* ctx_;
  RoiNormalizeShape shape_;
  const vk::Pipeline* pipeline_;  // borrowed from the context's registry
};

#if PENSIGHT_HAS_CUDA
// CUDA implementation (same result); throws pensight::Error when no CUDA device is present.
std::vector<float> roi_normalize_cuda(const ImageU8& image, std::span<const RoiOrigin> rois,
                                      int roi_size);
#endif

}  // namespace pensight::kernels
