#pragma once
// Accuracy of the dense-depth stage on a rendered dataset against its ground-truth depth
// (groundtruth0/depth/), with the two baselines it must beat measured on the same frames and
// pixels: S1 alone (every pixel the nearest prior's depth, in camera pixels) and the FFT plane
// extrapolated to every pixel (z = d_net / (1 - tan(psi) x - tan(pitch) y) on each pixel's ray);
// and, beside them, the prior surface the network corrects (pipeline/depth/prior_surface.h,
// fitted in camera pixels with the scene's net curvature, net_curvature_per_m; the estimator is
// expected to be configured with the same).
// Only frames with an FFT pose count (the network runs on those); only pixels whose truth sees
// the net (> 0) and that the network's view covers (a camera of another aspect: its centred
// crop, depth_input.h). The relative pose from dense depth is compared with groundtruth0's d_net
// and psi_net. Cost per frame: one detection, one network run, O(pixels) sums.
#include <cstddef>
#include <string>

#include "pipeline/dataset/dataset_reader.h"
#include "pipeline/depth/depth_estimator.h"
#include "pipeline/depth/dvl_depth_correction.h"
#include "pipeline/fft/net_detector.h"

namespace pensight {

struct DepthErrors {
  double abs_rel = 0;  // mean |z - z_true| / z_true over the pixels
  double delta1 = 0;   // share with max(z / z_true, z_true / z) < 1.25
  double rmse_m = 0;
  size_t pixels = 0;
};

struct DepthAccuracy {
  size_t frames = 0;  // with an FFT pose and ground truth
  DepthErrors network, s1, fft_plane, surface;
  double d_net_median_rel = 0;  // median |d_net_depth - d_net| / d_net
  double psi_median_rad = 0;    // median |psi_net_depth - psi_net|
  size_t pose_frames = 0;       // frames with a dense-depth pose and a truth d_net
  size_t scaled_frames = 0;     // scored frames whose depth the DVL's scale corrected
  size_t tilted_frames = 0;     // scored frames whose depth the DVL's tilt corrected
};

// Every `stride`-th frame. With `dvl` (fed the dataset's dvl0 samples; every frame then runs the
// stage, as in the pipeline) the network's depth and pose are those of the pipeline with the
// DVL's corrections (dvl_depth_correction.h); S1, the FFT plane and the prior surface stay the
// camera's alone. Throws pensight::Error when the dataset has no groundtruth0/depth/.
DepthAccuracy depth_accuracy(const Dataset& dataset, NetDetector& detector,
                             DepthEstimator& estimator, size_t stride = 1,
                             DvlDepthCorrection* dvl = nullptr);

}  // namespace pensight
