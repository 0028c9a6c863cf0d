#include "pipeline/depth/dvl_depth_scale.h"

#include <algorithm>
#include <cmath>

#include "core/error.h"
#include "core/median.h"
#include "core/units.h"

namespace pensight {

DvlDepthScale::DvlDepthScale(const PinholeCamera& camera, const Eigen::Isometry3d& T_body_camera,
                             const DvlCalibration& dvl, DvlDepthScaleConfig config)
    : camera_(camera),
      T_camera_body_(T_body_camera.inverse()),
      dvl_(dvl),
      config_(config),
      pairing_(config.max_pair_dt_s) {
  validate(config_);
  for (Eigen::Vector3d& u : dvl_.beam_directions_S) u.normalize();
}

void DvlDepthScale::add(const DvlSample& s) {
  if (!s.valid || !s.velocity_B_mps.allFinite()) return;
  int ranges = 0;
  for (double r : s.beam_range_m) ranges += std::isfinite(r) && r > 0;
  if (ranges >= 2) pairing_.add(s);
}

double DvlDepthScale::depth_at(const ImageF32& depth_m, const Eigen::Vector2d& px) const {
  const int cx = static_cast<int>(std::lround(px.x())), cy = static_cast<int>(std::lround(px.y()));
  const int h = config_.spot_half_px;
  std::vector<double> values;
  for (int y = std::max(0, cy - h); y <= std::min(depth_m.height - 1, cy + h); ++y) {
    for (int x = std::max(0, cx - h); x <= std::min(depth_m.width - 1, cx + h); ++x) {
      const float d = depth_m.at(x, y);
      if (std::isfinite(d) && d > 0) values.push_back(d);
    }
  }
  // Half the window at least: a spot on the net's edge or a hole gives no ratio.
  const int side = 2 * h + 1;
  return 2 * static_cast<int>(values.size()) >= side * side ? median(std::move(values)) : kNaN;
}

double DvlDepthScale::sample_log_ratio(const DvlSample& s, double dt_s,
                                       const ImageF32& depth_m) const {
  // The net is still: at the frame's time the body has moved by v dt, so the end point, fixed
  // in the pen, is that much nearer in the body frame.
  const Eigen::Vector3d moved_B = s.velocity_B_mps * dt_s;
  std::vector<double> beams;
  for (size_t i = 0; i < s.beam_range_m.size(); ++i) {
    const double r = s.beam_range_m[i];
    if (!(std::isfinite(r) && r > 0)) continue;
    const Eigen::Vector3d end_B = dvl_.T_body_dvl * (r * dvl_.beam_directions_S[i]) - moved_B;
    const Eigen::Vector3d end_C = T_camera_body_ * end_B;
    const auto px = camera_.project(end_C);
    if (!px || !camera_.in_image(*px)) continue;
    const double d = depth_at(depth_m, *px);
    if (std::isfinite(d)) beams.push_back(std::log(end_C.z() / d));
  }
  if (beams.size() < 2) return kNaN;
  // The middle of 2-4 values (the mean of the middle two when even): one fish in one beam of
  // three or four moves it by at most the spread of the others. Two beams (the lower two leave
  // the image within ~0.6 m of the net) cannot outvote each other: far apart, the sample is
  // dropped.
  std::sort(beams.begin(), beams.end());
  const size_t n = beams.size();
  if (n == 2 && beams[1] - beams[0] > config_.max_two_beam_spread) return kNaN;
  return n % 2 ? beams[n / 2] : 0.5 * (beams[n / 2 - 1] + beams[n / 2]);
}

DvlDepthScaleState DvlDepthScale::update(int64_t t_frame_ns, const ImageF32& depth_m) {
  check_image_size(depth_m.width, depth_m.height, camera_, "DvlDepthScale::update", "depth image");
  for (const DvlFramePairing::Paired& p : pairing_.take(t_frame_ns)) {
    const double lr = sample_log_ratio(p.sample, p.dt_s, depth_m);
    if (std::isfinite(lr)) window_.push_back({p.sample.timestamp_ns, lr});
  }
  const auto window_ns = seconds_to_ns_toward_zero(config_.window_s);
  while (!window_.empty() && window_.front().t_ns < t_frame_ns - window_ns) window_.pop_front();

  state_.samples = static_cast<int>(window_.size());
  if (state_.samples < config_.min_samples) {
    state_ = {.samples = state_.samples};
    return state_;
  }
  std::vector<double> lr;
  for (const Ratio& r : window_) lr.push_back(r.log_ratio);
  const auto [m, se] = median_with_error(lr);
  const double trusted = std::log1p(config_.trusted_rel);
  // Once engaged it stays so while the median is beyond the trusted band: a scale that flickers
  // on and off would step the depth by the whole stretch from frame to frame.
  state_.engaged =
      state_.engaged ? std::abs(m) > trusted : std::abs(m) > trusted + config_.confidence_z * se;
  state_.median_rel = std::expm1(m);
  state_.scale = state_.engaged ? std::exp(m) : 1.0;
  return state_;
}

ImageF32 scaled_depth(const ImageF32& depth_m, double scale) {
  ImageF32 out = depth_m;
  const auto s = static_cast<float>(scale);
  for (float& d : out.pixels) d *= s;
  return out;
}

}  // namespace pensight
