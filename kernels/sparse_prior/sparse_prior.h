#pragma once
// Prior maps for depth completion from sparse depths (TRUDepth's S1/S2): for every pixel the
// nearest sparse point in exact Euclidean pixel distance r,
//   S1 = depth of that point,  S2 = exp(-r^2 / (2 sigma^2)).
// Points are snapped to the pixel grid (x = floor(x_px + 0.5)), so r^2 is an integer and every
// implementation picks the same nearest point; ties go to the lowest point index. With no points
// S1 = 0 and r is the image diagonal (r^2 = W^2 + H^2).
// Output layout: two NCHW planes, S1 then S2, each row-major W x H, starting at a given element
// offset, so the maps land directly in channels c, c+1 of a network input tensor.
#include <cstdint>
#include <span>
#include <vector>

#include "runtime/vk_buffer.h"
#include "runtime/vk_pipeline.h"
#include "runtime/vk_stream.h"

namespace pensight::kernels {

struct SparsePoint {
  float x_px = 0;  // image coordinates of the network input resolution
  float y_px = 0;
  float depth_m = 0;
};

inline constexpr int kMaxSparsePoints = 1024;

struct SparsePriorShape {
  int width = 320;
  int height = 240;
  float sigma_px = 10;
};

// Throws pensight::Error naming the problem: bad shape, more than kMaxSparsePoints points, or a
// point that is not finite or does not snap to a pixel inside the image.
void validate(const SparsePriorShape& shape, std::span<const SparsePoint> points);

// Nearest point index per pixel (row-major), -1 when there are no points, and its squared
// distance. Brute force over all points: the reference the fast paths are tested against.
struct NearestMap {
  std::vector<int32_t> label;
  std::vector<int64_t> dist2_px2;
};
NearestMap nearest_brute_force(const SparsePriorShape& shape, std::span<const SparsePoint> points);
// The same map in O(W*H + K*H) (K = columns holding a point): Felzenszwalb-Huttenlocher's
// separable lower envelope, with each parabola's offset extended by the point index so the
// lexicographic (distance, index) minimum is unique at every pixel and ties are exact.
NearestMap nearest_exact_edt(const SparsePriorShape& shape, std::span<const SparsePoint> points);

// S1/S2 planes from a nearest map; `out` holds at least 2 * W * H floats.
void sparse_prior_from_nearest(const SparsePriorShape& shape, std::span<const SparsePoint> points,
                               const NearestMap& nearest, std::span<float> out);
// Reference (brute force) and fast CPU paths; identical labels, S2 equal to float rounding.
void sparse_prior_cpu_reference(const SparsePriorShape& shape, std::span<const SparsePoint> points,
                                std::span<float> out);
void sparse_prior_cpu(const SparsePriorShape& shape, std::span<const SparsePoint> points,
                      std::span<float> out);

// The per-frame scalars of SparsePriorVk::record. The shader reads them from a small device
// buffer when the stream runs (they are not baked into the recording), so the caller updates the
// buffer each frame, e.g. params.fill({n}), and resubmits the same stream.
struct SparsePriorParams {
  // Points used from the points buffer; the shader clamps it to the buffer's capacity and to
  // kMaxSparsePoints.
  uint32_t num_points = 0;
};

// Vulkan: one 16x16 tile per workgroup; the tile keeps only the points that can be nearest to
// one of its pixels (bounded by the smallest farthest-corner distance), then searches them.
class SparsePriorVk {
 public:
  SparsePriorVk(const vk::Context& ctx, const SparsePriorShape& shape);

  const SparsePriorShape& shape() const { return shape_; }
  // points: SparsePoint[capacity] holding params.num_points valid points (validated by the
  // caller: invalid points are clamped into the image); params: read when the stream runs; out:
  // floats, S1 at out_offset, S2 at out_offset + W*H (fixed per recording).
  void record(vk::CommandStream& stream, const vk::Buffer& points,
              const vk::TypedBuffer<SparsePriorParams>& params, const vk::Buffer& out,
              uint32_t out_offset = 0) const;

  // One-off convenience: validate, upload, run, download both planes.
  std::vector<float> run(std::span<const SparsePoint> points) const;

 private:
  const vk::Context* ctx_;
  SparsePriorShape shape_;
  const vk::Pipeline* pipeline_;  // borrowed from the context's registry
};

}  // namespace pensight::kernels
