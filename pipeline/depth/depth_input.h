#pragma once
// The depth network's inputs from a camera frame: the image area-resized to the network's
// resolution and the sparse priors moved into its pixel coordinates. The training data
// (sim/depth_training.h) and the depth stage go through these same functions, so the network
// sees at run time exactly the quantisation and geometry it was trained on.
#include <span>
#include <vector>

#include "core/camera.h"
#include "core/image.h"
#include "kernels/sparse_prior/sparse_prior.h"
#include "pipeline/fft/net_geometry.h"

namespace pensight {

// The network input resolution pensight's models use (720x540 scaled by 4/9).
inline constexpr int kDepthNetWidth = 320, kDepthNetHeight = 240;

// The part of the camera image a width x height network sees: the whole image where it has the
// network's aspect, else the largest centred crop of that aspect (a 4:3 network on a 16:9 camera
// sees its middle 4:3; the sides get no dense depth). Integer pixels; where the aspect cannot be
// met exactly the crop's side is rounded and x and y scale by slightly different factors.
struct NetworkView {
  int x0_px = 0, y0_px = 0;         // the crop's top-left camera pixel
  int width_px = 0, height_px = 0;  // the crop's size in camera pixels
};
NetworkView network_view(int camera_width, int camera_height, int width, int height);

// The camera seen through `view` at the network's width x height: the crop's principal point
// and focal lengths scaled by width / view.width_px and height / view.height_px, pixel centres at
// integers in both.
PinholeCamera network_camera(const PinholeCamera& camera, const NetworkView& view, int width,
                             int height);

// Area-average resize (each output pixel the mean of the input pixels it covers), rounded to
// 8 bits. Throws pensight::Error for an empty image or a non-positive size.
ImageU8 resize_area(const ImageU8& image, int width, int height);

// `view` of the image (network_view) area-resized to width x height.
ImageU8 network_image(const ImageU8& image, const NetworkView& view, int width, int height);

// Sparse depths from camera pixels (centres at integers) into the width x height network image
// of `view`: x' = (x - view.x0_px + 0.5) * width / view.width_px - 0.5, likewise y; points outside
// the view are dropped; depth, quality and order unchanged. At most kMaxSparsePoints are kept,
// highest quality first when there are more.
std::vector<SparseDepth> network_depths(std::span<const SparseDepth> depths,
                                        const NetworkView& view, int width, int height);

// The points of network_depths() without their quality, as the S1/S2 kernels take them.
std::vector<kernels::SparsePoint> points_of(std::span<const SparseDepth> depths);

}  // namespace pensight
