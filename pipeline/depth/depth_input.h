#pragma once
// The depth network's inputs from a camera frame: the image area-resized to the network's
// resolution and the sparse priors moved into its pixel coordinates. The training data
// (sim/depth_training.h) and the depth stage go through these same functions, so the network
// sees at run time exactly the quantisation and geometry it was trained on.
#include <span>
#include <vector>

#include "core/image.h"
#include "kernels/sparse_prior/sparse_prior.h"
#include "pipeline/fft/net_geometry.h"

namespace pensight {

// The network input resolution pensight's models use (720x540 scaled by 4/9).
inline constexpr int kDepthNetWidth = 320, kDepthNetHeight = 240;

// Area-average resize (each output pixel the mean of the input pixels it covers), rounded to
// 8 bits. Throws pensight::Error for an empty image or a non-positive size.
ImageU8 resize_area(const ImageU8& image, int width, int height);

// Sparse depths from camera pixels (centres at integers) into a width x height image of the same
// view: x' = (x + 0.5) * width / camera_width - 0.5, likewise y; depth, quality and order
// unchanged. At most kMaxSparsePoints are kept, highest quality first when there are more.
std::vector<SparseDepth> network_depths(std::span<const SparseDepth> depths, int camera_width,
                                        int camera_height, int width, int height);

// The points of network_depths() without their quality, as the S1/S2 kernels take them.
std::vector<kernels::SparsePoint> points_of(std::span<const SparseDepth> depths);

}  // namespace pensight
