#pragma once
// The net's tilt in the camera (psi_net, pitch_net) measured by a forward-looking DVL's four beam
// ranges, and applied to dense depth where the camera's own tilt is off.
//
// The FFT priors, and so the dense depth fitted to them, read the net's tilt from how the
// lattice's period changes across the image. A net whose bar length itself changes across the
// view (a stretch gradient: diamond.yaml's +-3 % over 3 m) looks turned: at 2 m the FFT's and the
// dense depth's psi are 2-3.5 deg off there, and no image shows it (docs/dense_depth.md). The
// plane through the DVL's four beam end points (global_pose/dvl_plane.h) does not depend on the
// lattice; per sample its tilt is noisier than the camera's on a uniform net (1 cm range noise:
// 0.4-0.7 deg median against the camera's 0.05-0.3 deg). So, as the bar length's scale does
// (dvl_depth_scale.h), the window's median of DVL minus dense depth replaces the camera's tilt
// only where it exceeds a trusted band, with confidence (its standard error from the window's
// MAD, floored by what the DVL's range noise gives over each sample's beam spread: the MAD of six
// samples is near 0 now and then); on the shipped scenarios' uniform nets it never does. The window
// is short, as the bias moves with the point the camera looks at.
//
// Not thread-safe; the pipeline's global-pose worker owns one (through dvl_depth_correction.h).
// Cost per frame: a 3x3 eigen-decomposition per new DVL sample and a median over the window
// (about 6 samples).
#include <Eigen/Geometry>
#include <cstdint>
#include <deque>

#include "core/dataset_types.h"
#include "core/image.h"
#include "core/units.h"
#include "pipeline/depth/depth_plane.h"
#include "pipeline/depth/dvl_frame_pairing.h"

namespace pensight {

struct DvlNetTiltConfig {
  // A DVL sample is paired with the first frame at or after it, at most this much later; the
  // body's rotation over that span is not compensated (0.5 deg at 10 deg/s over the mean 0.05 s;
  // the window's median averages it).
  double max_pair_dt_s = 0.1;
  double window_s = 1.5;         // the look point moves with the heading: about a metre in 3 s
  int min_samples = 5;           // 1.25 s of a 4 Hz DVL
  double trusted_rad = 0.01745;  // 1 deg: the camera's tilt is right within this
  double confidence_z = 3;       // |median| must exceed trusted_rad by this many standard errors
  // The four end points' RMS distance from their plane: beyond it a beam is on a fish or a rope
  // (1 cm range noise gives about 5 mm).
  double max_residual_m = 0.03;
  // The DVL's range noise (1 sigma, its data sheet's): with the beams' spread it gives each
  // sample's angle noise, the floor of the window's standard error.
  double range_noise_m = 0.01;
};

// Throws pensight::Error "depth: key 'dvl_net_tilt.KEY': VALUE is outside RANGE UNIT (HELP)" for
// the first value out of its range (depth_param_rows() lists them).
void validate(const DvlNetTiltConfig& config);

struct DvlNetTiltState {
  // Added to the dense depth's psi and pitch; 0 on an axis that is not engaged.
  double psi_offset_rad = 0, pitch_offset_rad = 0;
  bool psi_engaged = false, pitch_engaged = false;
  int samples = 0;  // in the window
  // The window's medians of the DVL's angle minus the dense depth's (NaN below min_samples).
  double psi_diff_rad = kNaN, pitch_diff_rad = kNaN;
  bool engaged() const { return psi_engaged || pitch_engaged; }
};

class DvlNetTilt {
 public:
  // Throws like validate(config).
  DvlNetTilt(const Eigen::Isometry3d& T_body_camera, const DvlCalibration& dvl,
             DvlNetTiltConfig config = {});

  // A DVL sample in timestamp order; invalid ones and those without four finite positive ranges
  // are ignored.
  void add(const DvlSample& s);

  // The frame at t_frame_ns with its pose from dense depth (before this correction): pairs the
  // DVL samples at most max_pair_dt_s before it, updates the window and returns the offsets to
  // add. A pose that is not valid adds nothing to the window.
  DvlNetTiltState update(int64_t t_frame_ns, const DepthPlanePose& depth_pose);

  const DvlNetTiltState& state() const { return state_; }

 private:
  struct Diff {
    int64_t t_ns;
    double psi_rad, pitch_rad;
    double sigma_psi_rad, sigma_pitch_rad;  // from the range noise and the beams' spread
  };

  Eigen::Isometry3d T_body_camera_, T_camera_body_;
  DvlCalibration dvl_;
  DvlNetTiltConfig config_;
  DvlFramePairing pairing_;
  std::deque<Diff> window_;
  DvlNetTiltState state_;
};

// The depth of the surface turned with the net plane z = a x + b y + c of `pose` (a = tan psi,
// b = tan pitch) about its point on the optical axis to psi + dpsi_rad, pitch + dpitch_rad: each
// pixel's depth times (1 - a x - b y) / (1 - a' x - b' y) on its ray (x, y, 1). The optical
// axis's depth, and so d_net, is unchanged. A ray that no longer meets the turned plane in front
// gets 0 (no estimate), as holes stay 0. Throws pensight::Error when the image's size is not the
// rays'. Cost: one pass over the pixels.
ImageF32 tilted_depth(const ImageF32& depth_m, const PixelRays& rays, const DepthPlanePose& pose,
                      double dpsi_rad, double dpitch_rad);

}  // namespace pensight
