#pragma once
// A world known in closed form for the DVL's corrections of dense depth: a flat net in front of a
// vehicle moving at constant velocity without turning, seen by the simulator's camera mount and
// Janus DVL with its range and velocity noise. The camera's depth can be made wrong the two ways
// the lattice makes it wrong: too near by a stretch (the bar length is `stretch` times
// scene.yaml's), and turned by psi / pitch biases about its point on the optical axis.
#include <Eigen/Geometry>
#include <cmath>
#include <random>

#include "core/camera.h"
#include "core/dataset_types.h"
#include "core/image.h"
#include "core/units.h"

namespace pensight::testing {

// The simulator's camera mount: 0.3 m ahead of the body origin, looking along body x.
inline Eigen::Isometry3d camera_mount() {
  Eigen::Matrix3d R;
  R << 0, 0, 1, 1, 0, 0, 0, 1, 0;
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = R;
  T.translation() = Eigen::Vector3d(0.3, 0, 0);
  return T;
}

// A flat net n . X = d in the frame of the body at t = 0.
struct FlatNetWorld {
  Eigen::Vector3d normal;  // unit, away from the vehicle
  double d_m;
  Eigen::Vector3d velocity_B_mps;
  double stretch = 1;                           // the camera sees the net this much nearer
  double psi_bias_rad = 0, pitch_bias_rad = 0;  // the camera sees the net turned by these

  double range(const Eigen::Vector3d& origin, const Eigen::Vector3d& dir) const {
    const double nd = normal.dot(dir);
    const double t = nd > 1e-6 ? (d_m - normal.dot(origin)) / nd : kNaN;
    return t > 0 ? t : kNaN;
  }

  // The net's true psi_net and pitch_net in the camera (docs/conventions.md).
  Eigen::Vector2d true_tilt_rad(const Eigen::Isometry3d& T_bc) const {
    const Eigen::Vector3d m = T_bc.linear().transpose() * normal;
    return {std::atan2(-m.x(), m.z()), std::atan2(-m.y(), m.z())};
  }

  // The camera's z-depth: the true plane z = a x + b y + c (camera frame) with psi and pitch
  // biased about its point on the optical axis, divided by the stretch.
  ImageF32 camera_depth(const PinholeCamera& cam, const Eigen::Isometry3d& T_bc, double t_s) const {
    const Eigen::Vector3d origin = velocity_B_mps * t_s + T_bc.translation();
    const Eigen::Vector2d tilt = true_tilt_rad(T_bc);
    const double a = std::tan(tilt.x() + psi_bias_rad), b = std::tan(tilt.y() + pitch_bias_rad);
    const double c = range(origin, T_bc.linear() * Eigen::Vector3d::UnitZ());
    ImageF32 depth(cam.width_px, cam.height_px);
    for (int y = 0; y < cam.height_px; ++y) {
      for (int x = 0; x < cam.width_px; ++x) {
        const Eigen::Vector3d ray_C = cam.ray({x, y});  // z = 1
        const double den = 1 - a * ray_C.x() - b * ray_C.y();
        depth.at(x, y) = den > 1e-6 ? static_cast<float>(c / den / stretch) : 0.0f;
      }
    }
    return depth;
  }

  DvlSample dvl_sample(const DvlCalibration& dvl, double t_s, std::mt19937_64& rng) const {
    std::normal_distribution<double> range_noise(0, 0.01), velocity_noise(0, 0.005);
    DvlSample s;
    s.timestamp_ns = seconds_to_ns(t_s);
    s.valid = true;
    s.velocity_B_mps = velocity_B_mps + Eigen::Vector3d(velocity_noise(rng), velocity_noise(rng),
                                                        velocity_noise(rng));
    const Eigen::Vector3d origin = velocity_B_mps * t_s + dvl.T_body_dvl.translation();
    for (size_t i = 0; i < 4; ++i) {
      const Eigen::Vector3d dir = dvl.T_body_dvl.linear() * dvl.beam_directions_S[i].normalized();
      s.beam_range_m[i] = range(origin, dir) + range_noise(rng);
    }
    return s;
  }
};

// A net 0.6-2 m from the camera, up to 25 deg off square and 10 deg pitched, the vehicle moving
// along it at 0.1-0.3 m/s and towards or away from it at up to 0.01 m/s.
inline FlatNetWorld random_flat_net_world(std::mt19937_64& rng, double stretch) {
  std::uniform_real_distribution<double> yaw(-0.44, 0.44), pitch(-0.17, 0.17), dist(0.6, 2.0),
      along(0.1, 0.3), radial(-0.01, 0.01), sign(-1, 1);
  FlatNetWorld w;
  const double a = yaw(rng);
  w.normal = Eigen::AngleAxisd(pitch(rng), Eigen::Vector3d::UnitY()) *
             Eigen::Vector3d(std::cos(a), std::sin(a), 0);
  w.d_m = w.normal.dot(Eigen::Vector3d(0.3 + dist(rng), 0, 0));
  const Eigen::Vector3d tangent = w.normal.cross(Eigen::Vector3d::UnitZ()).normalized();
  w.velocity_B_mps = along(rng) * (sign(rng) < 0 ? -1 : 1) * tangent + radial(rng) * w.normal;
  w.stretch = stretch;
  return w;
}

}  // namespace pensight::testing
