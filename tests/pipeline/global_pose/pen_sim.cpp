#include "tests/pipeline/global_pose/pen_sim.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "core/units.h"

namespace pensight::global_pose::sim {

Eigen::Isometry3d Pose::T_pen_body() const {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = rotation_from_rpy(roll_rad, pitch_rad, yaw_rad);
  T.translation() = p_pen;
  return T;
}

Eigen::Isometry3d forward_camera() {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  // Columns: camera x -> body y (right), camera y -> body z (down), optical axis -> body x.
  T.linear() << 0, 0, 1, 1, 0, 0, 0, 1, 0;
  T.translation() = Eigen::Vector3d(0.3, 0.0, 0.1);
  return T;
}

DvlCalibration forward_dvl() {
  DvlCalibration dvl;
  dvl.T_body_dvl.linear() = forward_camera().linear();
  dvl.T_body_dvl.translation() = Eigen::Vector3d(0.4, 0.0, 0.2);
  const double off = 22.5 * std::numbers::pi / 180.0;
  for (int i = 0; i < 4; ++i) {
    const double az = std::numbers::pi / 4 + i * std::numbers::pi / 2;
    dvl.beam_directions_S[i] =
        Eigen::Vector3d(std::sin(off) * std::cos(az), std::sin(off) * std::sin(az), std::cos(off));
  }
  return dvl;
}

void add_texture_steps(Sequence& seq, double radius_m, const Eigen::Isometry3d& T_body_camera,
                       double bar_length_m, double sigma_bars, std::mt19937_64& rng) {
  std::normal_distribution<double> unit(0.0, 1.0);
  const auto axis_point = [&](const Pose& pose) {
    const Eigen::Isometry3d T = pose.T_pen_body() * T_body_camera;
    const Eigen::Vector3d dir = T.linear().col(2);
    return Eigen::Vector3d(T.translation() +
                           ray_to_cylinder(T.translation(), dir, radius_m).value() * dir);
  };
  for (size_t k = 1; k < seq.camera.size(); ++k) {
    const Eigen::Vector3d a = axis_point(seq.truth[k - 1]), b = axis_point(seq.truth[k]);
    const double azimuth = std::atan2(b.y(), b.x());
    // The mesh's bars at b: along the wall (increasing azimuth) and down.
    const Eigen::Vector3d along(-std::sin(azimuth), std::cos(azimuth), 0);
    const double moved[2] = {
        radius_m * wrap_angle(azimuth - std::atan2(a.y(), a.x())) / bar_length_m,
        (b.z() - a.z()) / bar_length_m};
    const Eigen::Matrix3d R_camera_pen =
        (seq.truth[k].T_pen_body() * T_body_camera).linear().transpose();
    TextureStep& s = seq.camera[k].texture;
    s.valid = true;
    s.from_ns = seq.camera[k - 1].t_ns;
    s.ray_C = Eigen::Vector3d::UnitZ();
    s.bars_C = {bar_length_m * R_camera_pen * along,
                bar_length_m * R_camera_pen * Eigen::Vector3d::UnitZ()};
    for (size_t i = 0; i < 2; ++i) {
      const double m = moved[i] + sigma_bars * unit(rng);
      s.moved_bars[i] = m - std::floor(m + 0.5);
    }
  }
}

NetObservation net_observation(const Pose& pose, double radius_m,
                               const Eigen::Isometry3d& T_body_camera, const PointNoise& noise,
                               std::mt19937_64& rng, const PinholeCamera& camera) {
  NetObservation obs;
  obs.t_ns = kStart_ns + seconds_to_ns(pose.t_s);
  const Eigen::Isometry3d T_pen_camera = pose.T_pen_body() * T_body_camera;
  std::normal_distribution<double> unit(0.0, 1.0);
  std::uniform_real_distribution<double> u01(0.0, 1.0);
  for (int r = 0; r < 5; ++r) {
    for (int c = 0; c < 6; ++c) {
      // Centres of the 300 px ROIs of the default grid on 720x540.
      const Eigen::Vector2d px(150.0 + c * 84.0, 150.0 + r * 60.0);
      const Eigen::Vector3d dir_C = camera.ray(px).normalized();
      const auto t =
          ray_to_cylinder(T_pen_camera.translation(), T_pen_camera.linear() * dir_C, radius_m);
      if (!t || *t > noise.max_range_m) {
        obs.points_C.push_back(Eigen::Vector3d::Constant(kNaN));
        obs.quality.push_back(0.0);
        continue;
      }
      double range = *t * (1.0 + noise.range_sigma_frac * unit(rng));
      if (u01(rng) < noise.outlier_fraction) range += noise.outlier_sigma_m * unit(rng);
      obs.points_C.push_back(std::max(range, 0.05) * dir_C);
      obs.quality.push_back(1.0);
    }
  }
  const auto rel = net_relative_pose(T_pen_camera, NetWall::cylinder(radius_m));
  obs.d_net_m = rel.d_net_m * (1.0 + noise.d_net_sigma_frac * unit(rng));
  obs.psi_net_rad = rel.psi_net_rad + noise.psi_net_sigma_rad * unit(rng);
  return obs;
}

Pose Trajectory::at(double t_s) const {
  const double two_pi = 2 * std::numbers::pi;
  const double d = mean_distance_m + distance_amp_m * std::sin(two_pi * t_s / 40.0);
  const double r = radius_m - d;
  const double rho = speed_mps * t_s / (radius_m - mean_distance_m) + 0.3;
  Pose p;
  p.t_s = t_s;
  p.p_pen = Eigen::Vector3d(r * std::cos(rho), r * std::sin(rho),
                            depth_m + depth_amp_m * std::sin(two_pi * t_s / 60.0));
  p.yaw_rad = wrap_angle(rho + psi_r_amp_rad * std::sin(two_pi * t_s / 27.0));
  p.roll_rad = roll_pitch_amp_rad * std::sin(two_pi * t_s / 11.0);
  p.pitch_rad = roll_pitch_amp_rad * std::sin(two_pi * t_s / 17.0 + 1.0);
  return p;
}

Eigen::Vector3d Trajectory::body_velocity(double t_s) const {
  const double h = 1e-4;
  const Eigen::Vector3d v_pen = (at(t_s + h).p_pen - at(t_s - h).p_pen) / (2 * h);
  const Pose p = at(t_s);
  return rotation_from_rpy(p.roll_rad, p.pitch_rad, p.yaw_rad).transpose() * v_pen;
}

namespace {
int64_t to_ns(double t_s) {
  return kStart_ns + seconds_to_ns(t_s);
}
}  // namespace

Sequence make_sequence(const Trajectory& traj, const SensorNoise& noise, uint64_t seed,
                       const Eigen::Isometry3d& T_body_camera, const DvlCalibration& dvl) {
  Sequence seq;
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> unit(0.0, 1.0);
  for (double t = 0.0; t <= traj.duration_s; t += 0.1) {
    seq.truth.push_back(traj.at(t));
    seq.camera.push_back(
        net_observation(seq.truth.back(), traj.radius_m, T_body_camera, noise.points, rng));
  }
  for (double t = 0.013; t <= traj.duration_s; t += 0.25) {
    DvlSample s;
    s.timestamp_ns = to_ns(t);
    s.valid = true;
    const Eigen::Vector3d v = traj.body_velocity(t);
    s.velocity_B_mps = (1.0 + noise.dvl_scale_error) * v + noise.dvl_bias_mps +
                       noise.dvl_sigma_mps * Eigen::Vector3d(unit(rng), unit(rng), unit(rng));
    const auto ranges =
        dvl_ranges_to_wall(dvl, traj.at(t).T_pen_body(), NetWall::cylinder(traj.radius_m));
    for (size_t i = 0; i < 4; ++i) {
      if (ranges[i] < 30.0) s.beam_range_m[i] = ranges[i] + noise.dvl_range_sigma_m * unit(rng);
    }
    seq.dvl.push_back(s);
  }
  for (double t = 0.031; t <= traj.duration_s; t += 0.125)
    seq.depth.push_back({to_ns(t), traj.at(t).p_pen.z() + noise.depth_sigma_m * unit(rng)});
  for (double t = 0.007; t <= traj.duration_s; t += 0.05) {
    const Pose p = traj.at(t);
    seq.attitude.push_back(
        {to_ns(t), p.roll_rad + noise.attitude_sigma_rad * unit(rng),
         p.pitch_rad + noise.attitude_sigma_rad * unit(rng),
         wrap_angle(p.yaw_rad + noise.yaw_offset_rad + noise.yaw_drift_radps * t +
                    noise.yaw_sigma_rad * unit(rng))});
  }
  return seq;
}

void replay(const Sequence& seq, const Visitor& visit) {
  size_t id = 0, ip = 0, ia = 0, ic = 0;
  const int64_t never = std::numeric_limits<int64_t>::max();
  for (;;) {
    const int64_t td = id < seq.dvl.size() ? seq.dvl[id].timestamp_ns : never;
    const int64_t tp = ip < seq.depth.size() ? seq.depth[ip].timestamp_ns : never;
    const int64_t ta = ia < seq.attitude.size() ? seq.attitude[ia].timestamp_ns : never;
    const int64_t tc = ic < seq.camera.size() ? seq.camera[ic].t_ns : never;
    const int64_t t = std::min({td, tp, ta, tc});
    if (t == never) return;
    if (t == ta) {
      if (visit.attitude) visit.attitude(seq.attitude[ia]);
      ++ia;
    } else if (t == td) {
      if (visit.dvl) visit.dvl(seq.dvl[id]);
      ++id;
    } else if (t == tp) {
      if (visit.depth) visit.depth(seq.depth[ip]);
      ++ip;
    } else {
      if (visit.camera) visit.camera(seq.camera[ic], seq.truth[ic]);
      ++ic;
    }
  }
}

double percentile(std::vector<double> v, double p) {
  if (v.empty()) return kNaN;
  std::sort(v.begin(), v.end());
  const double pos = p * static_cast<double>(v.size() - 1);
  const size_t i = static_cast<size_t>(pos);
  const double f = pos - static_cast<double>(i);
  return i + 1 < v.size() ? v[i] * (1 - f) + v[i + 1] * f : v[i];
}

double median(std::vector<double> v) {
  return percentile(std::move(v), 0.5);
}

}  // namespace pensight::global_pose::sim
