#pragma once
// Net-relative pose from a dense depth image: d_net is the mean depth of a central window, psi and
// pitch the slopes of a robust plane z = a x + b y + c over every valid back-projected pixel
// (psi = atan(a), pitch = atan(b), as the FFT pose and ../shared/dataset-format.md define them).
//
// Method: a consensus start (the best of `hypotheses` three-pixel planes, scored on a strided
// subset of ~2000 pixels), then iteratively reweighted least squares over every valid pixel on
// the 3x3 normal equations (one O(pixels) pass per iteration) with Tukey's biweight, its scale
// 4.685 x kMadToSigma (core/median.h) x the median residual of the pixels within inlier_rel of the
// plane; so fish, ropes or a second surface in view do not tilt the plane. d_net averages the
// central window's pixels on the plane. A pixel is valid when its depth is finite and > 0. Cost at
// 320x240: about a millisecond.
#include <Eigen/Core>
#include <string>
#include <vector>

#include "core/camera.h"
#include "core/image.h"
#include "core/units.h"

namespace pensight {

struct DepthPlaneParams {
  double central_share = 0.2;  // d_net window: this share of the width and height, centred
  int hypotheses = 64;
  double inlier_rel = 0.05;  // residual / depth that still counts as on the net (as the FFT pose)
  int iterations = 4;
  double min_valid_share = 0.05;  // fewer valid pixels: NaN
};

struct DepthPlanePose {
  double d_net_m = kNaN, psi_net_rad = kNaN, pitch_net_rad = kNaN;
  double inlier_share = 0;               // pixels with a non-zero final weight
  std::string reason = "not estimated";  // why the pose is NaN; empty when valid
  bool valid() const { return reason.empty(); }
};

// Every pixel's ray (z = 1) of a camera, computed once: undistorting is the costly part of a
// back-projection, and a stage sees the same camera every frame.
struct PixelRays {
  int width = 0, height = 0;
  Eigen::Vector2d centre_px = Eigen::Vector2d::Zero();  // the principal point
  std::vector<Eigen::Vector2f> xy;                      // row-major (x, y) of each ray
  explicit PixelRays(const PinholeCamera& camera);
};

// `rays` are those of the camera the depth image is registered to. Throws pensight::Error when
// the image size differs from theirs.
DepthPlanePose depth_plane_pose(const ImageF32& depth_m, const PixelRays& rays,
                                const DepthPlaneParams& params = {});

}  // namespace pensight
