#pragma once
// Sparse depths for the depth-completion network from the FFT detection: several per inlier ROI,
// each on that ROI's local net surface, so the network's prior maps (S1/S2) carry the net's slope
// inside every ROI rather than one constant patch per ROI centre.
//
// The local surface of a ROI is the plane through its net point p_C with the frame's fitted
// normal (relative_pose_fft.h): the ROI's own tilt is ambiguous in sign and biased low by a few
// per cent, and the frame's plane is not, while p_C keeps the ROI's own range (the wall's
// curvature and bulges). The samples sit on a per_axis x per_axis grid centred on the ROI's
// point, `spacing_share` of the ROI side apart, inside the image. Each carries the ROI's
// spectral quality as its confidence. Cost: O(inlier ROIs x per_axis^2), microseconds.
#include <span>
#include <vector>

#include "core/camera.h"
#include "core/params.h"
#include "pipeline/fft/net_geometry.h"
#include "pipeline/fft/relative_pose_fft.h"

namespace pensight {

struct DepthPriorParams {
  int per_axis = 3;             // samples per ROI: per_axis^2 (1: the ROI's point alone)
  double spacing_share = 0.25;  // grid step as a share of the ROI side
};

// Key, unit, valid range and help of every DepthPriorParams member (NetDetectorConfig::priors).
std::span<const Param<DepthPriorParams>> depth_prior_params();

// Empty when the pose is not valid. Samples whose ray misses the plane (grazing) or falls outside
// the image are left out. Throws pensight::Error when a parameter is outside its range
// (depth_prior_params) or `rois` and pose.inlier differ in length.
std::vector<SparseDepth> roi_surface_priors(std::span<const RoiNetPoint> rois,
                                            const FftRelativePose& pose, int roi_size_px,
                                            const PinholeCamera& camera,
                                            const DepthPriorParams& params = {});

}  // namespace pensight
