#pragma once
// Internal to CUDA implementation files: block-wide reductions.

namespace pensight::cuda {

// Sum of v over a block of kThreads threads (a power of two) through `partial`, a shared array of
// kThreads floats. Every thread must call it (it synchronises); all receive the total.
template <int kThreads>
__device__ float block_sum(float v, float* partial) {
  partial[threadIdx.x] = v;
  __syncthreads();
  for (int s = kThreads / 2; s > 0; s /= 2) {
    if (threadIdx.x < s) partial[threadIdx.x] += partial[threadIdx.x + s];
    __syncthreads();
  }
  const float total = partial[0];
  __syncthreads();
  return total;
}

}  // namespace pensight::cuda
