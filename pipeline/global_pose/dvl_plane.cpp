#include "pipeline/global_pose/dvl_plane.h"

#include <Eigen/Eigenvalues>
#include <cmath>

#include "core/net_angles.h"

namespace pensight::global_pose {

NetRelativePose DvlPlane::in_camera(const Eigen::Isometry3d& T_body_camera) const {
  if (!ok) return {};
  // n.p_B = distance with p_B = R p_C + t  =>  (R^T n).p_C = distance - n.t
  const Eigen::Vector3d m = T_body_camera.linear().transpose() * normal_B;
  const double offset = distance_m - normal_B.dot(T_body_camera.translation());
  if (!(m.z() > 1e-9) || !(offset > 0)) return {};
  const NetAngles angles = net_angles_from_normal_C(m);
  return {offset / m.z(), angles.psi_rad, angles.pitch_rad};
}

DvlPlane dvl_net_plane(const DvlCalibration& dvl, const std::array<double, 4>& range_m,
                       double roll_rad, double pitch_rad) {
  DvlPlane plane;
  std::array<Eigen::Vector3d, 4> pts;
  int n = 0;
  for (size_t i = 0; i < 4; ++i) {
    if (!(std::isfinite(range_m[i]) && range_m[i] > 0)) continue;
    pts[n++] = dvl.T_body_dvl * (range_m[i] * dvl.beam_directions_S[i].normalized());
  }
  plane.beams = n;
  if (n < 3) return plane;
  Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
  for (int i = 0; i < n; ++i) centroid += pts[i];
  centroid /= n;
  Eigen::Matrix3d scatter = Eigen::Matrix3d::Zero();
  for (int i = 0; i < n; ++i) scatter += (pts[i] - centroid) * (pts[i] - centroid).transpose();
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(scatter);
  // Collinear end points (e.g. two beams lost in a Janus pair's plane) define no plane.
  if (!(eig.eigenvalues()(1) > 1e-6 * eig.eigenvalues()(2))) return plane;
  Eigen::Vector3d normal = eig.eigenvectors().col(0);
  if (normal.dot(centroid) < 0) normal = -normal;
  plane.normal_B = normal;
  plane.distance_m = normal.dot(centroid);
  plane.residual_rms_m = std::sqrt(std::max(0.0, eig.eigenvalues()(0)) / n);
  const Eigen::Vector3d n_L = rotation_level_body(roll_rad, pitch_rad) * normal;
  plane.heading_rad = -std::atan2(n_L.y(), n_L.x());
  plane.ok = std::isfinite(plane.distance_m) && std::isfinite(plane.heading_rad);
  return plane;
}

std::array<double, 4> dvl_ranges_to_wall(const DvlCalibration& dvl,
                                         const Eigen::Isometry3d& T_pen_body, const NetWall& wall) {
  const Eigen::Isometry3d T_pen_dvl = T_pen_body * dvl.T_body_dvl;
  std::array<double, 4> ranges = {kNaN, kNaN, kNaN, kNaN};
  for (size_t i = 0; i < 4; ++i) {
    const auto t = wall.ray_distance(T_pen_dvl.translation(),
                                     T_pen_dvl.linear() * dvl.beam_directions_S[i].normalized());
    if (t) ranges[i] = *t;
  }
  return ranges;
}

}  // namespace pensight::global_pose
