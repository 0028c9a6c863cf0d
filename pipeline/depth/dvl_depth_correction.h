#pragma once
// The DVL's corrections of dense depth, in the order the pipeline and the depth evaluation apply
// them: the net's tilt (dvl_net_tilt.h: the image turned about the optical axis's net point, psi
// and pitch offset), then the net's bar length (dvl_depth_scale.h: the image and d_net scaled),
// each only where its config is set and only while it is engaged.
//
// Not thread-safe; the pipeline's global-pose worker owns one. Costs per frame: the two updates
// (microseconds) and, while a correction is engaged, one pass over the image for each.
#include <Eigen/Geometry>
#include <optional>

#include "core/camera.h"
#include "core/dataset_types.h"
#include "core/image.h"
#include "pipeline/depth/depth_plane.h"
#include "pipeline/depth/dvl_depth_scale.h"
#include "pipeline/depth/dvl_net_tilt.h"

namespace pensight {

struct DvlDepthCorrected {
  DvlDepthScaleState scale;
  DvlNetTiltState tilt;
  std::optional<ImageF32> depth_m;  // the corrected depth; unset when nothing is engaged
};

class DvlDepthCorrection {
 public:
  // Throws pensight::Error when a set config is not usable (see the two classes).
  DvlDepthCorrection(const PinholeCamera& camera, const Eigen::Isometry3d& T_body_camera,
                     const DvlCalibration& dvl, const std::optional<DvlDepthScaleConfig>& scale,
                     const std::optional<DvlNetTiltConfig>& tilt);

  void add(const DvlSample& s);

  // The frame at t_frame_ns with its dense depth (camera resolution) and the pose from it:
  // updates both corrections and applies those engaged to `pose` (in place) and to a copy of the
  // image. Precondition: depth_m has the camera's size (else pensight::Error).
  DvlDepthCorrected apply(int64_t t_frame_ns, const ImageF32& depth_m, DepthPlanePose& pose);

 private:
  std::optional<DvlDepthScale> scale_;
  std::optional<DvlNetTilt> tilt_;
  std::optional<PixelRays> rays_;  // with the tilt
};

}  // namespace pensight
