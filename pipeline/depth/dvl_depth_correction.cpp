#include "pipeline/depth/dvl_depth_correction.h"

namespace pensight {

DvlDepthCorrection::DvlDepthCorrection(const PinholeCamera& camera,
                                       const Eigen::Isometry3d& T_body_camera,
                                       const DvlCalibration& dvl,
                                       const std::optional<DvlDepthScaleConfig>& scale,
                                       const std::optional<DvlNetTiltConfig>& tilt) {
  if (scale) scale_.emplace(camera, T_body_camera, dvl, *scale);
  if (tilt) {
    tilt_.emplace(T_body_camera, dvl, *tilt);
    rays_.emplace(camera);
  }
}

void DvlDepthCorrection::add(const DvlSample& s) {
  if (scale_) scale_->add(s);
  if (tilt_) tilt_->add(s);
}

DvlDepthCorrected DvlDepthCorrection::apply(int64_t t_frame_ns, const ImageF32& depth_m,
                                            DepthPlanePose& pose) {
  DvlDepthCorrected out;
  // The tilt first: it compares angles, which a common scale does not change, and the scale's
  // ratios at the beams' spots are then read off a depth no longer turned (a 3 deg turn moves
  // them by +-1.7 % across the beams at 2 m).
  if (tilt_) {
    out.tilt = tilt_->update(t_frame_ns, pose);
    if (out.tilt.engaged() && pose.valid()) {
      out.depth_m =
          tilted_depth(depth_m, *rays_, pose, out.tilt.psi_offset_rad, out.tilt.pitch_offset_rad);
      pose.psi_net_rad += out.tilt.psi_offset_rad;
      pose.pitch_net_rad += out.tilt.pitch_offset_rad;
    }
  }
  if (scale_) {
    const ImageF32& turned = out.depth_m ? *out.depth_m : depth_m;
    out.scale = scale_->update(t_frame_ns, turned);
    if (out.scale.engaged) {
      out.depth_m = scaled_depth(turned, out.scale.scale);
      pose.d_net_m *= out.scale.scale;
    }
  }
  return out;
}

}  // namespace pensight
