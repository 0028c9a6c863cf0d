#include "kernels/roi_normalize/roi_normalize.h"
#include "runtime/cuda_check.cuh"
#include "runtime/cuda_reduce.cuh"

namespace pensight::kernels {
namespace {

constexpr int kThreads = 256;

// One block per ROI. Pixels are shifted by the ROI's first pixel before summing so that a flat
// ROI gives exactly zero variance in float, as in the Vulkan shader.
__global__ void roi_normalize_kernel(const uint8_t* image, int width, const RoiOrigin* rois,
                                     int size, float* out) {
  __shared__ float partial[kThreads];
  const RoiOrigin o = rois[blockIdx.x];
  const int n = size * size;
  const float ref = image[o.y * width + o.x];
  auto pixel = [&](int i) { return image[(o.y + i / size) * width + o.x + i % size] - ref; };
  float s = 0;
  for (int i = threadIdx.x; i < n; i += kThreads) s += pixel(i);
  const float mean = cuda::block_sum<kThreads>(s, partial) / n;
  float q = 0;
  for (int i = threadIdx.x; i < n; i += kThreads) {
    const float d = pixel(i) - mean;
    q += d * d;
  }
  const float var = cuda::block_sum<kThreads>(q, partial) / n;
  const float inv_std = var > kFlatVariance ? rsqrtf(var) : 0.0f;
  float* dst = out + static_cast<size_t>(blockIdx.x) * n;
  for (int i = threadIdx.x; i < n; i += kThreads) dst[i] = (pixel(i) - mean) * inv_std;
}

}  // namespace

std::vector<float> roi_normalize_cuda(const ImageU8& image, std::span<const RoiOrigin> rois,
                                      int roi_size) {
  validate({image.width, image.height, 8, roi_size}, rois);
  if (rois.empty()) return {};
  const size_t n = static_cast<size_t>(roi_size) * roi_size * rois.size();
  cuda::DeviceArray<uint8_t> d_image(image.pixels.size());
  cuda::DeviceArray<RoiOrigin> d_rois(rois.size());
  cuda::DeviceArray<float> d_out(n);
  d_image.upload(image.pixels.data(), image.pixels.size());
  d_rois.upload(rois.data(), rois.size());
  roi_normalize_kernel<<<static_cast<unsigned>(rois.size()), kThreads>>>(
      d_image.data(), image.width, d_rois.data(), roi_size, d_out.data());
  PENSIGHT_CUDA(cudaGetLastError());
  return d_out.to_vector();
}

}  // namespace pensight::kernels
