#pragma once
// The default camera's size and focal length, apart from core/camera.h (Eigen) so that CUDA
// sources read the same numbers without Eigen's host-only constexpr functions.

namespace pensight {

// The default camera: the published pipeline's 720 x 540 px at fx = fy = 462 px, principal
// point at the image centre.
inline constexpr int kDefaultImageWidth_px = 720;
inline constexpr int kDefaultImageHeight_px = 540;
inline constexpr double kDefaultFocalLength_px = 462.0;

}  // namespace pensight
