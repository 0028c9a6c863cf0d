#pragma once
// The net's angles in the camera frame C, as the dataset contract defines them
// (docs/conventions.md): psi_net = atan2(-m_x, m_z) and pitch_net = atan2(-m_y, m_z) from the net
// normal m_C (pointing away from the camera, into the net), equivalently psi_net = atan(a) and
// pitch_net = atan(b) from the net plane z = a x + b y + c in C (normal (-a, -b, 1)).
#include <Eigen/Core>
#include <cmath>

#include "core/units.h"

namespace pensight {

struct NetAngles {
  double psi_rad = kNaN, pitch_rad = kNaN;
};

// From the net normal in C, pointing into the net (m_z > 0 for a net in front of the camera).
inline NetAngles net_angles_from_normal_C(const Eigen::Vector3d& m_C) {
  return {std::atan2(-m_C.x(), m_C.z()), std::atan2(-m_C.y(), m_C.z())};
}

// From the slopes a = dz/dx and b = dz/dy of the net plane z = a x + b y + c in C: the angles of
// net_angles_from_normal_C((-a, -b, 1)), by atan, which can differ from atan2 in the last bit.
inline NetAngles net_angles_from_plane_C(double a, double b) {
  return {std::atan(a), std::atan(b)};
}

}  // namespace pensight
