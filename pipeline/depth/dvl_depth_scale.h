#pragma once
// The net's true bar length against scene.yaml's, measured by a forward-looking DVL's beam ranges
// and applied to dense depth.
//
// Every metric depth the camera gives comes from the bar length: a net stretched 3 % under load
// (or a nominal mesh size 3 % off) puts every FFT prior, and so the dense depth, 3 % too near,
// and no image shows it. The DVL's four ranges are metric without it. Each DVL sample's beam end
// points, moved to the frame's time by the DVL's own velocity, are projected into the frame; the
// ratio of their depth to the dense depth there is the bar length's scale. Over a window the
// median of those ratios (robust to a fish or a rope in one beam) replaces the scene.yaml scale
// only where it differs from 1 by more than the bar length is trusted to, with confidence
// (median's standard error from the window's MAD): on the shipped scenarios' nets, at their
// nominal size, the window's median reads -0.5 to +0.9 % (docs/dense_depth.md), so the trusted
// 1.5 % keeps those frames exactly as the camera gives them.
//
// Not thread-safe; the pipeline's global-pose worker owns one. Costs per frame: a projection and
// a 5x5 median per beam of each new DVL sample, and a median over the window (about 40 samples):
// about a microsecond (bench/depth_stage_bench.cpp).
#include <Eigen/Geometry>
#include <cstdint>
#include <deque>
#include <vector>

#include "core/camera.h"
#include "core/dataset_types.h"
#include "core/image.h"
#include "pipeline/depth/dvl_frame_pairing.h"

namespace pensight {

struct DvlDepthScaleConfig {
  // A DVL sample is paired with the first frame at or after it, at most this much later; the
  // body's rotation over that span is not compensated (0.02 rad at 0.2 rad/s).
  double max_pair_dt_s = 0.1;
  double window_s = 10;        // the net's stretch varies over metres, the vehicle moves slowly
  int min_samples = 8;         // 2 s of a 4 Hz DVL
  double trusted_rel = 0.015;  // scene.yaml's bar length is right within this
  double confidence_z = 3;     // |median| must exceed trusted_rel by this many standard errors
  int spot_half_px = 2;        // the dense depth at a beam spot: median over a 5x5 window
  // Two beams whose log ratios differ by more: one of them is not on the net (1 cm range noise
  // at 0.5 m is 2.8 % on their difference).
  double max_two_beam_spread = 0.1;
};

// Throws pensight::Error "depth: key 'dvl_depth_scale.KEY': VALUE is outside RANGE UNIT (HELP)"
// for the first value out of its range (depth_param_rows() lists them).
void validate(const DvlDepthScaleConfig& config);

struct DvlDepthScaleState {
  double scale = 1;          // multiplies dense depth; 1 when not engaged
  bool engaged = false;      // the DVL's scale replaces scene.yaml's
  int samples = 0;           // in the window
  double median_rel = kNaN;  // window median of the DVL / image depth ratio, minus 1
};

class DvlDepthScale {
 public:
  // Throws like validate(config).
  DvlDepthScale(const PinholeCamera& camera, const Eigen::Isometry3d& T_body_camera,
                const DvlCalibration& dvl, DvlDepthScaleConfig config = {});

  // A DVL sample in timestamp order; invalid ones and those without two finite positive ranges
  // are ignored. Pending samples more than max_pair_dt_s older than it are dropped (no frame can
  // pair them any more).
  void add(const DvlSample& s);

  // The frame at t_frame_ns with its dense z-depth (camera resolution, metres, 0 or NaN = none):
  // pairs the DVL samples at most max_pair_dt_s before it (older unpaired ones are dropped),
  // updates the window and returns the scale to apply to this frame's depth.
  // Precondition: depth_m has the camera's size (else pensight::Error).
  DvlDepthScaleState update(int64_t t_frame_ns, const ImageF32& depth_m);

  const DvlDepthScaleState& state() const { return state_; }

 private:
  struct Ratio {
    int64_t t_ns;
    double log_ratio;
  };
  double sample_log_ratio(const DvlSample& s, double dt_s, const ImageF32& depth_m) const;
  double depth_at(const ImageF32& depth_m, const Eigen::Vector2d& px) const;

  PinholeCamera camera_;
  Eigen::Isometry3d T_camera_body_;
  DvlCalibration dvl_;
  DvlDepthScaleConfig config_;
  DvlFramePairing pairing_;
  std::deque<Ratio> window_;
  DvlDepthScaleState state_;
};

// Multiplies every finite depth by `scale` (a new image; 0 stays 0).
ImageF32 scaled_depth(const ImageF32& depth_m, double scale);

}  // namespace pensight
