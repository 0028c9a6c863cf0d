#include "pipeline/depth/dvl_net_tilt.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <vector>

#include "core/error.h"
#include "core/median.h"
#include "core/units.h"
#include "pipeline/global_pose/dvl_plane.h"

namespace pensight {

DvlNetTilt::DvlNetTilt(const Eigen::Isometry3d& T_body_camera, const DvlCalibration& dvl,
                       DvlNetTiltConfig config)
    : T_body_camera_(T_body_camera),
      T_camera_body_(T_body_camera.inverse()),
      dvl_(dvl),
      config_(config),
      pairing_(config.max_pair_dt_s) {
  validate(config_);
}

void DvlNetTilt::add(const DvlSample& s) {
  if (!s.valid) return;
  for (double r : s.beam_range_m) {
    if (!(std::isfinite(r) && r > 0)) return;
  }
  pairing_.add(s);
}

DvlNetTiltState DvlNetTilt::update(int64_t t_frame_ns, const DepthPlanePose& depth_pose) {
  for (const DvlFramePairing::Paired& p : pairing_.take(t_frame_ns)) {
    if (!depth_pose.valid()) continue;
    // Four beams: a fish or a rope in one of them shows as the residual, where three would fit
    // any plane.
    const global_pose::DvlPlane plane = global_pose::dvl_net_plane(dvl_, p.sample.beam_range_m);
    if (!plane.ok || plane.beams < 4 || !(plane.residual_rms_m <= config_.max_residual_m)) continue;
    const global_pose::NetRelativePose dvl = plane.in_camera(T_body_camera_);
    if (!std::isfinite(dvl.psi_net_rad) || !std::isfinite(dvl.pitch_net_rad)) continue;
    // The slopes' standard errors of a least-squares plane z = a x + b y + c through the end
    // points (camera frame) with the DVL's range noise along z: sigma / sqrt(sum (x - mean)^2).
    Eigen::Vector2d spread = Eigen::Vector2d::Zero(), mean = Eigen::Vector2d::Zero();
    std::array<Eigen::Vector2d, 4> xy;
    for (size_t i = 0; i < 4; ++i) {
      const Eigen::Vector3d end_C =
          T_camera_body_ *
          (dvl_.T_body_dvl * (p.sample.beam_range_m[i] * dvl_.beam_directions_S[i].normalized()));
      xy[i] = end_C.head<2>();
      mean += xy[i] / 4;
    }
    for (const Eigen::Vector2d& v : xy) spread += (v - mean).cwiseAbs2();
    const double cos2_psi = std::pow(std::cos(dvl.psi_net_rad), 2);
    const double cos2_pitch = std::pow(std::cos(dvl.pitch_net_rad), 2);
    window_.push_back({p.sample.timestamp_ns, wrap_angle(dvl.psi_net_rad - depth_pose.psi_net_rad),
                       wrap_angle(dvl.pitch_net_rad - depth_pose.pitch_net_rad),
                       config_.range_noise_m * cos2_psi / std::sqrt(spread.x()),
                       config_.range_noise_m * cos2_pitch / std::sqrt(spread.y())});
  }
  const auto window_ns = seconds_to_ns_toward_zero(config_.window_s);
  while (!window_.empty() && window_.front().t_ns < t_frame_ns - window_ns) window_.pop_front();

  const int samples = static_cast<int>(window_.size());
  if (samples < config_.min_samples) {
    state_ = {.samples = samples};
    return state_;
  }
  std::vector<double> psi, pitch;
  double var_psi = 0, var_pitch = 0;
  for (const Diff& d : window_) {
    psi.push_back(d.psi_rad);
    pitch.push_back(d.pitch_rad);
    var_psi += d.sigma_psi_rad * d.sigma_psi_rad / samples;
    var_pitch += d.sigma_pitch_rad * d.sigma_pitch_rad / samples;
  }
  // Once engaged an axis stays so while its median is beyond the band: an offset that flickers
  // on and off would swing the pose by the whole offset from frame to frame.
  const auto engaged = [&](bool was, const MedianWithError& m) {
    return was ? std::abs(m.median) > config_.trusted_rad
               : std::abs(m.median) > config_.trusted_rad + config_.confidence_z * m.standard_error;
  };
  // The MAD of a few samples is near 0 by chance now and then: the range noise's standard error
  // of the median is its floor.
  const auto with_floor = [&](MedianWithError m, double var) {
    m.standard_error =
        std::max(m.standard_error, kMedianErrorOverMeanError * std::sqrt(var / samples));
    return m;
  };
  const MedianWithError m_psi = with_floor(median_with_error(psi), var_psi);
  const MedianWithError m_pitch = with_floor(median_with_error(pitch), var_pitch);
  state_.samples = samples;
  state_.psi_engaged = engaged(state_.psi_engaged, m_psi);
  state_.pitch_engaged = engaged(state_.pitch_engaged, m_pitch);
  state_.psi_diff_rad = m_psi.median;
  state_.pitch_diff_rad = m_pitch.median;
  state_.psi_offset_rad = state_.psi_engaged ? m_psi.median : 0;
  state_.pitch_offset_rad = state_.pitch_engaged ? m_pitch.median : 0;
  return state_;
}

ImageF32 tilted_depth(const ImageF32& depth_m, const PixelRays& rays, const DepthPlanePose& pose,
                      double dpsi_rad, double dpitch_rad) {
  if (depth_m.width != rays.width || depth_m.height != rays.height) {
    throw Error("tilted_depth: the depth image is " + std::to_string(depth_m.width) + "x" +
                std::to_string(depth_m.height) + ", the camera's " + std::to_string(rays.width) +
                "x" + std::to_string(rays.height));
  }
  const double a = std::tan(pose.psi_net_rad), b = std::tan(pose.pitch_net_rad);
  const double a2 = std::tan(pose.psi_net_rad + dpsi_rad);
  const double b2 = std::tan(pose.pitch_net_rad + dpitch_rad);
  ImageF32 out = depth_m;
  for (size_t p = 0; p < out.pixels.size(); ++p) {
    float& z = out.pixels[p];
    if (!(std::isfinite(z) && z > 0)) continue;
    const Eigen::Vector2f& r = rays.xy[p];
    const double before = 1 - a * r.x() - b * r.y(), after = 1 - a2 * r.x() - b2 * r.y();
    // Rays nearly parallel to either plane: the ratio is meaningless there.
    z = before > 1e-3 && after > 1e-3 ? static_cast<float>(z * before / after) : 0.0f;
  }
  return out;
}

}  // namespace pensight
