#include <cstring>

#include "kernels/roi_normalize/roi_normalize.h"
#include "runtime/error.h"
#include "runtime/vk_buffer.h"

namespace pensight::kernels {
namespace {

struct RoiNormalizePush {
  uint32_t num_rois;
};

}  // namespace

RoiNormalizeVk::RoiNormalizeVk(const vk::Context& ctx, const RoiNormalizeShape& shape)
    : ctx_(&ctx),
      shape_((validate(shape, {}), shape)),
      pipeline_(&ctx.pipeline({.shader = "roi_normalize/roi_normalize",
                               .num_buffers = 3,
                               .push_constant_bytes = sizeof(RoiNormalizePush),
                               .specialization = {static_cast<uint32_t>(shape.width),
                                                  static_cast<uint32_t>(shape.height),
                                                  static_cast<uint32_t>(shape.bits),
                                                  static_cast<uint32_t>(shape.roi_size)}})) {}

size_t RoiNormalizeVk::image_bytes() const {
  const size_t bytes = static_cast<size_t>(shape_.width) * shape_.height * (shape_.bits / 8);
  return (bytes + 3) / 4 * 4;
}

void RoiNormalizeVk::record(vk::CommandStream& stream, const vk::Buffer& image,
                            const vk::Buffer& rois, const vk::Buffer& out,
                            uint32_t num_rois) const {
  const size_t n = static_cast<size_t>(shape_.roi_size) * shape_.roi_size;
  if (image.size_bytes() < image_bytes() || rois.size_bytes() < num_rois * sizeof(RoiOrigin) ||
      out.size_bytes() < num_rois * n * sizeof(float)) {
    throw Error("RoiNormalizeVk::record: a buffer is smaller than the shape needs");
  }
  stream.dispatch(*pipeline_, {vk::in(image), vk::in(rois), vk::out(out)}, {num_rois, 1, 1},
                  RoiNormalizePush{num_rois}, "roi_normalize");
}

template <class Pixel>
std::vector<float> RoiNormalizeVk::run_impl(const Image<Pixel>& image,
                                            std::span<const RoiOrigin> rois) const {
  if (image.width != shape_.width || image.height != shape_.height ||
      static_cast<int>(sizeof(Pixel) * 8) != shape_.bits) {
    throw Error("RoiNormalizeVk::run: image is " + std::to_string(image.width) + "x" +
                std::to_string(image.height) + "x" + std::to_string(sizeof(Pixel) * 8) +
                " bit, the kernel was built for " + std::to_string(shape_.width) + "x" +
                std::to_string(shape_.height) + "x" + std::to_string(shape_.bits) + " bit");
  }
  validate(shape_, rois);
  if (rois.empty()) return {};
  const size_t n = static_cast<size_t>(shape_.roi_size) * shape_.roi_size * rois.size();
  vk::Buffer image_buf(*ctx_, image_bytes());
  image_buf.upload(image.pixels.data(), image.pixels.size() * sizeof(Pixel));
  vk::Buffer roi_buf(*ctx_, rois.size_bytes());
  roi_buf.upload(rois.data(), rois.size_bytes());
  vk::TypedBuffer<float> out(*ctx_, n);
  vk::CommandStream stream(*ctx_);
  record(stream, image_buf, roi_buf, out.raw(), static_cast<uint32_t>(rois.size()));
  stream.submit_and_wait();
  return out.to_vector();
}

std::vector<float> RoiNormalizeVk::run(const ImageU8& image,
                                       std::span<const RoiOrigin> rois) const {
  return run_impl(image, rois);
}

std::vector<float> RoiNormalizeVk::run(const ImageU16& image,
                                       std::span<const RoiOrigin> rois) const {
  return run_impl(image, rois);
}

}  // namespace pensight::kernels
