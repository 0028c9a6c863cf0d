#include <bit>
#include <string>

#include "core/error.h"
#include "kernels/kernel_shader.h"
#include "kernels/sparse_prior/sparse_prior.h"
#include "kernels/sparse_prior/sparse_prior_detail.h"
#include "runtime/vk_buffer.h"

namespace pensight::kernels {
namespace {

constexpr uint32_t kTile = 16;  // must match local_size in sparse_prior.comp

struct SparsePriorPush {
  uint32_t out_offset;
};

static_assert(sizeof(SparsePriorParams) == 4, "must match Params in sparse_prior.comp");

}  // namespace

SparsePriorVk::SparsePriorVk(const vk::Context& ctx, const SparsePriorShape& shape)
    : ctx_(&ctx),
      shape_((validate(shape, {}), shape)),
      pipeline_(&ctx.pipeline(
          {.shader = kernel_shader("sparse_prior/sparse_prior"),
           .num_buffers = 3,
           .push_constant_bytes = sizeof(SparsePriorPush),
           .specialization = {static_cast<uint32_t>(shape.width),
                              static_cast<uint32_t>(shape.height),
                              std::bit_cast<uint32_t>(detail::inv_two_sigma2(shape))}})) {}

void SparsePriorVk::record(vk::CommandStream& stream, const vk::Buffer& points,
                           const vk::TypedBuffer<SparsePriorParams>& params, const vk::Buffer& out,
                           uint32_t out_offset) const {
  const size_t plane = static_cast<size_t>(shape_.width) * shape_.height;
  if (points.size_bytes() < sizeof(SparsePoint) || params.size() < 1 ||
      out.size_bytes() < (out_offset + 2 * plane) * sizeof(float)) {
    throw Error(
        "SparsePriorVk::record: the points buffer holds no point, the params buffer is "
        "empty, or the output buffer is smaller than 2 planes of " +
        std::to_string(shape_.width) + "x" + std::to_string(shape_.height) + " at offset " +
        std::to_string(out_offset) + " need");
  }
  const vk::Groups groups{(static_cast<uint32_t>(shape_.width) + kTile - 1) / kTile,
                          (static_cast<uint32_t>(shape_.height) + kTile - 1) / kTile, 1};
  stream.dispatch(*pipeline_, {vk::in(points), vk::out(out), vk::in(params)}, groups,
                  SparsePriorPush{out_offset}, "sparse_prior");
}

std::vector<float> SparsePriorVk::run(std::span<const SparsePoint> points) const {
  validate(shape_, points);
  vk::Buffer point_buf(*ctx_, std::max<size_t>(points.size_bytes(), sizeof(SparsePoint)));
  if (!points.empty()) point_buf.upload(points.data(), points.size_bytes());
  vk::TypedBuffer<SparsePriorParams> params(*ctx_, 1);
  params.fill({static_cast<uint32_t>(points.size())});
  vk::TypedBuffer<float> out(*ctx_, 2 * static_cast<size_t>(shape_.width) * shape_.height);
  vk::CommandStream stream(*ctx_);
  record(stream, point_buf, params, out.raw());
  stream.submit_and_wait();
  return out.to_vector();
}

}  // namespace pensight::kernels
