#include "pipeline/fft/depth_priors.h"

#include <cmath>
#include <limits>
#include <string>

#include "core/error.h"

namespace pensight {

namespace {

const Param<DepthPriorParams> kDepthPriorParams[] = {
    {"per_axis",
     &DepthPriorParams::per_axis,
     "",
     {1, std::numeric_limits<double>::infinity()},
     "samples per ROI and axis: per_axis^2 per ROI (1: the ROI's point alone)"},
    {"spacing_share",
     &DepthPriorParams::spacing_share,
     "",
     {0, 0.5, true, false},
     "grid step of a ROI's samples as a share of the ROI side"},
};

}  // namespace

std::span<const Param<DepthPriorParams>> depth_prior_params() {
  return kDepthPriorParams;
}

std::vector<SparseDepth> roi_surface_priors(std::span<const RoiNetPoint> rois,
                                            const FftRelativePose& pose, int roi_size_px,
                                            const PinholeCamera& camera,
                                            const DepthPriorParams& params) {
  check_params(params, depth_prior_params(), "depth priors");
  std::vector<SparseDepth> out;
  if (!pose.valid()) return out;
  if (pose.inlier.size() != rois.size()) {
    throw Error("depth priors: " + std::to_string(rois.size()) + " ROIs but " +
                std::to_string(pose.inlier.size()) + " inlier flags");
  }
  const Eigen::Vector3d n =
      net_plane_normal(std::tan(pose.psi_net_rad), std::tan(pose.pitch_net_rad));
  const double step_px = params.spacing_share * roi_size_px;
  const double half = 0.5 * (params.per_axis - 1);
  // A ray closer than this to the plane's direction meets it beyond any range the FFT resolves.
  constexpr double kMinCosine = 0.05;
  for (size_t i = 0; i < rois.size(); ++i) {
    if (!pose.inlier[i]) continue;
    const RoiNetPoint& p = rois[i];
    const double offset = n.dot(p.p_C);
    for (int gy = 0; gy < params.per_axis; ++gy) {
      for (int gx = 0; gx < params.per_axis; ++gx) {
        const Eigen::Vector2d px = p.centre_px + step_px * Eigen::Vector2d(gx - half, gy - half);
        if (!camera.in_image(px)) continue;
        const Eigen::Vector3d ray = camera.ray(px);  // z = 1, so the scale t is the depth
        const double along = n.dot(ray);
        if (std::abs(along) < kMinCosine * ray.norm()) continue;
        const double depth_m = offset / along;
        if (!(depth_m > 0) || !std::isfinite(depth_m)) continue;
        out.push_back(
            {{static_cast<float>(px.x()), static_cast<float>(px.y()), static_cast<float>(depth_m)},
             static_cast<float>(p.quality)});
      }
    }
  }
  return out;
}

}  // namespace pensight
