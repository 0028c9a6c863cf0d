#include "pipeline/depth/depth_accuracy.h"

#include <algorithm>
#include <cmath>
#include <vector>

#include "core/error.h"
#include "core/median.h"
#include "kernels/sparse_prior/sparse_prior.h"
#include "pipeline/depth/depth_input.h"
#include "pipeline/depth/prior_surface.h"

namespace pensight {
namespace {

struct Sums {
  double abs_rel = 0, sq = 0;
  size_t within = 0, n = 0;
  void add(double z, double truth) {
    abs_rel += std::abs(z - truth) / truth;
    sq += (z - truth) * (z - truth);
    within += std::max(z / truth, truth / z) < 1.25;
    ++n;
  }
  DepthErrors errors() const {
    if (n == 0) return {};
    const double count = static_cast<double>(n);
    return {abs_rel / count, static_cast<double>(within) / count, std::sqrt(sq / count), n};
  }
};

}  // namespace

DepthAccuracy depth_accuracy(const Dataset& dataset, NetDetector& detector,
                             DepthEstimator& estimator, size_t stride, DvlDepthCorrection* dvl) {
  if (!dataset.groundtruth0 || !dataset.groundtruth0->has_depth) {
    throw Error("'" + dataset.root.string() +
                "' has no groundtruth0/depth/: the depth accuracy needs a rendered dataset");
  }
  const PinholeCamera& cam = dataset.cam0.camera;
  const kernels::SparsePriorShape camera_shape{cam.width_px, cam.height_px};  // S1 only
  const PixelRays rays(cam);
  Sums network, s1, plane, surface;
  std::vector<double> d_errors, psi_errors;
  DepthAccuracy out;
  // With the DVL's corrections every frame runs the stage (the DVL samples pair with the frames
  // as in the pipeline); every stride-th is scored.
  const size_t step = dvl ? 1 : std::max<size_t>(stride, 1);
  size_t next_dvl = 0;
  for (size_t i = 0; i < dataset.frames.size(); i += step) {
    const int64_t t_ns = dataset.frames[i].timestamp_ns;
    if (dvl && dataset.dvl0) {
      const std::vector<DvlSample>& samples = dataset.dvl0->samples;
      for (; next_dvl < samples.size() && samples[next_dvl].timestamp_ns <= t_ns; ++next_dvl) {
        dvl->add(samples[next_dvl]);
      }
    }
    const bool scored = i % std::max<size_t>(stride, 1) == 0;
    const GroundTruthRow* truth = dataset.truth_for_frame(i);
    if (!dvl && !truth) continue;
    const ImageU8 image = dataset.load_frame(i);
    const NetDetection detection = detector.detect(image, t_ns);
    if (!detection.pose.valid() || detection.depths.empty()) continue;
    DenseDepth dense = estimator.estimate(image, detection.depths);
    if (!dense.reason.empty()) continue;
    if (dvl) {
      DvlDepthCorrected c = dvl->apply(t_ns, dense.depth_m, dense.pose);
      if (c.depth_m) dense.depth_m = std::move(*c.depth_m);
      if (scored && truth) {
        out.scaled_frames += c.scale.engaged;
        out.tilted_frames += c.tilt.engaged();
      }
    }
    if (!scored || !truth) continue;
    ++out.frames;
    std::vector<float> s1_maps(2 * static_cast<size_t>(cam.width_px) * cam.height_px);
    kernels::sparse_prior_cpu(camera_shape, points_of(detection.depths), s1_maps);
    std::vector<float> surface_m(static_cast<size_t>(cam.width_px) * cam.height_px);
    render_prior_surface(fit_prior_surface(detection.depths, cam.width_px, cam.height_px,
                                           {.curvature_per_m = net_curvature_per_m(dataset.scene),
                                            .focal_px = cam.fx_px}),
                         surface_m);
    const double a = std::tan(detection.pose.psi_net_rad);
    const double b = std::tan(detection.pose.pitch_net_rad);
    const ImageU16 truth_mm = dataset.load_depth_mm(i);
    for (size_t p = 0; p < truth_mm.pixels.size(); ++p) {
      if (truth_mm.pixels[p] == 0 || !std::isfinite(dense.depth_m.pixels[p])) continue;
      const double z_true = truth_mm.pixels[p] * 1e-3;
      const Eigen::Vector2f& r = rays.xy[p];
      network.add(dense.depth_m.pixels[p], z_true);
      s1.add(s1_maps[p], z_true);
      surface.add(surface_m[p], z_true);
      const double denom = 1 - a * r.x() - b * r.y();
      // A ray parallel to (or beyond) the plane gets no extrapolated depth: counted as its worst.
      plane.add(denom > 1e-3 ? detection.pose.d_net_m / denom : 1e3, z_true);
    }
    if (dense.pose.valid() && std::isfinite(truth->d_net_m)) {
      ++out.pose_frames;
      d_errors.push_back(std::abs(dense.pose.d_net_m - truth->d_net_m) / truth->d_net_m);
      psi_errors.push_back(std::abs(dense.pose.psi_net_rad - truth->psi_net_rad));
    }
  }
  out.network = network.errors();
  out.s1 = s1.errors();
  out.fft_plane = plane.errors();
  out.surface = surface.errors();
  if (!d_errors.empty()) {
    out.d_net_median_rel = median(d_errors);
    out.psi_median_rad = median(psi_errors);
  }
  return out;
}

}  // namespace pensight
