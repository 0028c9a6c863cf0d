#include "pipeline/dataset/sensor_mounts.h"

#include <cmath>
#include <numbers>

namespace pensight {

Eigen::Isometry3d forward_mount(const Eigen::Vector3d& position_B_m, double pan_rad,
                                double tilt_rad) {
  Eigen::Matrix3d forward;  // columns: sensor x, y, z in the body frame
  forward << 0, 0, 1, 1, 0, 0, 0, 1, 0;
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = (Eigen::AngleAxisd(pan_rad, Eigen::Vector3d::UnitZ()) *
                Eigen::AngleAxisd(-tilt_rad, Eigen::Vector3d::UnitY()))
                   .toRotationMatrix() *
               forward;
  T.translation() = position_B_m;
  return T;
}

DvlCalibration janus_dvl_calibration(double rate_hz, const Eigen::Isometry3d& T_body_dvl,
                                     double beam_angle_rad) {
  DvlCalibration c;
  c.rate_hz = rate_hz;
  c.T_body_dvl = T_body_dvl;
  for (size_t k = 0; k < 4; ++k) {
    const double phi = std::numbers::pi / 4 + std::numbers::pi / 2 * static_cast<double>(k);
    c.beam_directions_S[k] =
        Eigen::Vector3d(std::sin(beam_angle_rad) * std::cos(phi),
                        std::sin(beam_angle_rad) * std::sin(phi), std::cos(beam_angle_rad));
  }
  return c;
}

}  // namespace pensight
