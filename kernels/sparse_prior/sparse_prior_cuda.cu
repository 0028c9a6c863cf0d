#include "kernels/sparse_prior/sparse_prior.h"
#include "kernels/sparse_prior/sparse_prior_detail.h"
#include "runtime/cuda_check.cuh"

namespace pensight::kernels {
namespace {

constexpr int kTile = 16;

// One thread per pixel; the points are staged in shared memory and searched in index order
// (strict comparison: the lowest index wins a tie), with integer squared distances.
__global__ void sparse_prior_kernel(const SparsePoint* points, int num_points, int width,
                                    int height, float inv_two_sigma2, float* out) {
  __shared__ int2 xy[kMaxSparsePoints];
  const int lid = threadIdx.y * kTile + threadIdx.x;
  for (int i = lid; i < num_points; i += kTile * kTile) {
    xy[i] = make_int2(static_cast<int>(floorf(points[i].x_px + 0.5f)),
                      static_cast<int>(floorf(points[i].y_px + 0.5f)));
  }
  __syncthreads();
  const int x = blockIdx.x * kTile + threadIdx.x, y = blockIdx.y * kTile + threadIdx.y;
  if (x >= width || y >= height) return;
  long long best = static_cast<long long>(width) * width + static_cast<long long>(height) * height;
  int label = -1;
  for (int i = 0; i < num_points; ++i) {
    const long long dx = x - xy[i].x, dy = y - xy[i].y;
    const long long d2 = dx * dx + dy * dy;
    if (d2 < best) {  // every point is closer than the empty distance
      best = d2;
      label = i;
    }
  }
  const size_t plane = static_cast<size_t>(width) * height, p = static_cast<size_t>(y) * width + x;
  out[p] = label < 0 ? 0.f : points[label].depth_m;
  out[plane + p] = expf(-static_cast<float>(best) * inv_two_sigma2);
}

}  // namespace

std::vector<float> sparse_prior_cuda(const SparsePriorShape& shape,
                                     std::span<const SparsePoint> points) {
  validate(shape, points);
  const size_t n = 2 * static_cast<size_t>(shape.width) * shape.height;
  cuda::DeviceArray<SparsePoint> d_points(points.empty() ? 1 : points.size());
  cuda::DeviceArray<float> d_out(n);
  if (!points.empty()) d_points.upload(points.data(), points.size());
  const dim3 block(kTile, kTile);
  const dim3 grid((shape.width + kTile - 1) / kTile, (shape.height + kTile - 1) / kTile);
  sparse_prior_kernel<<<grid, block>>>(d_points.data(), static_cast<int>(points.size()),
                                       shape.width, shape.height, detail::inv_two_sigma2(shape),
                                       d_out.data());
  PENSIGHT_CUDA(cudaGetLastError());
  return d_out.to_vector();
}

}  // namespace pensight::kernels
