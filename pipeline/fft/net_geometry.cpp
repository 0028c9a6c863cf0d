#include "pipeline/fft/net_geometry.h"

#include <Eigen/Geometry>
#include <Eigen/SVD>
#include <algorithm>
#include <cmath>
#include <numbers>
#include <string>

#include "core/error.h"
#include "core/units.h"

namespace pensight {

const char* to_string(RoiStatus status) {
  switch (status) {
    case RoiStatus::kValid:
      return "valid";
    case RoiStatus::kNoLattice:
      return "no net lattice";
    case RoiStatus::kPartial:
      return "net covers part of the ROI";
    case RoiStatus::kTooFine:
      return "lattice too fine";
    case RoiStatus::kTooOblique:
      return "net too oblique";
    case RoiStatus::kBadGeometry:
      return "inconsistent lattice geometry";
  }
  return "unknown";
}

namespace {

// Lagrange-Gauss reduction of the lattice spanned by a (pixels), with lengths measured by m (the
// same vectors in a metric space, metres on the net or the frontal image): the shortest pair of
// independent vectors. A step is taken only when it shortens the longer vector to at most
// `max_ratio` of its length. Returns whether the basis changed.
bool reduce_basis(Eigen::Matrix2d& a, std::array<Eigen::Vector3d, 2>& m, double max_ratio) {
  bool changed = false;
  for (int iter = 0; iter < 32; ++iter) {
    if (m[0].squaredNorm() > m[1].squaredNorm()) {
      std::swap(m[0], m[1]);
      a.col(0).swap(a.col(1));
    }
    const double mu = std::round(m[0].dot(m[1]) / m[0].squaredNorm());
    if (mu == 0) break;
    const Eigen::Vector3d shorter = m[1] - mu * m[0];
    if (!(shorter.squaredNorm() <= max_ratio * max_ratio * m[1].squaredNorm())) break;
    m[1] = shorter;
    a.col(1) -= mu * a.col(0);
    changed = true;
  }
  return changed;
}

}  // namespace

Eigen::Vector3d ray_on_plane(const Eigen::Vector3d& ray, const Eigen::Vector3d& point_C,
                             const Eigen::Vector3d& normal_C) {
  return ray * (normal_C.dot(point_C) / normal_C.dot(ray));
}

std::array<Eigen::Vector3d, 2> bars_on_plane(const RoiNetPoint& roi, const PinholeCamera& camera,
                                             const Eigen::Vector3d& point_C,
                                             const Eigen::Vector3d& normal_C) {
  std::array<Eigen::Vector3d, 2> bars;
  for (int i = 0; i < 2; ++i) {
    const Eigen::Vector2d h = 0.5 * (i == 0 ? roi.lattice1_px : roi.lattice2_px);
    bars[static_cast<size_t>(i)] = ray_on_plane(camera.ray(roi.centre_px + h), point_C, normal_C) -
                                   ray_on_plane(camera.ray(roi.centre_px - h), point_C, normal_C);
  }
  return bars;
}

RoiNetPoint roi_net_point(const kernels::RoiLattice& lattice, kernels::RoiOrigin origin,
                          int roi_size_px, const PinholeCamera& camera, const MeshModel& mesh,
                          const NetPointParams& params, const Eigen::Vector3d* normal_hint_C) {
  if (!(mesh.bar_length_m > 0)) {
    throw Error("roi_net_point: net mesh size must be > 0 m, got " +
                std::to_string(mesh.bar_length_m) + "; set net_mesh_size_m in scene.yaml");
  }
  if (!(mesh.opening_angle_rad > 0 && mesh.opening_angle_rad < std::numbers::pi)) {
    throw Error("roi_net_point: mesh opening angle must be within (0, 180) deg, got " +
                std::to_string(rad_to_deg(mesh.opening_angle_rad)) +
                "; set net_mesh_angle_deg in scene.yaml");
  }
  RoiNetPoint out;
  out.origin = origin;
  out.quality = lattice.quality;
  // The lattice was measured where the ROI's energy is: on the net part of a ROI at its edge.
  out.centre_px =
      Eigen::Vector2d(origin.x + 0.5 * (roi_size_px - 1), origin.y + 0.5 * (roi_size_px - 1));
  if (params.use_centroid)
    out.centre_px += Eigen::Vector2d(lattice.centroid_dx, lattice.centroid_dy);
  if (!(lattice.quality >= params.min_quality)) return out;
  const double cycles =
      static_cast<double>(roi_size_px) *
      std::min<double>(std::hypot(lattice.f1x, lattice.f1y), std::hypot(lattice.f2x, lattice.f2y));
  if (cycles < params.near_cycles && !(lattice.quality >= params.near_min_quality)) return out;
  if (std::hypot(lattice.centroid_dx, lattice.centroid_dy) >
      params.max_centroid_share * roi_size_px) {
    out.status = RoiStatus::kPartial;
    return out;
  }

  Eigen::Matrix2d f;
  f << lattice.f1x, lattice.f2x, lattice.f1y, lattice.f2y;
  if (!(std::abs(f.determinant()) > 1e-12)) {
    out.status = RoiStatus::kBadGeometry;
    return out;
  }
  Eigen::Matrix2d a = f.inverse().transpose();  // a_i . f_j = delta_ij
  out.lattice1_px = a.col(0);
  out.lattice2_px = a.col(1);

  // Lattice vectors in the normalised, undistorted image (central differences through ray()).
  const Eigen::Vector3d r = camera.ray(out.centre_px);
  auto normalised = [&](const Eigen::Matrix2d& px) {
    Eigen::Matrix2d b;
    for (int i = 0; i < 2; ++i) {
      const Eigen::Vector2d h = 0.5 * px.col(i);
      b.col(i) = (camera.ray(out.centre_px + h) - camera.ray(out.centre_px - h)).head<2>();
    }
    return b;
  };
  // Virtual rotation R taking the centre ray onto +z; its image Jacobian there is R_2x2 / |r|.
  const Eigen::Matrix3d rot =
      Eigen::Quaterniond::FromTwoVectors(r.normalized(), Eigen::Vector3d::UnitZ())
          .toRotationMatrix();
  // The bars, and their signs for the acute angle, in the net's metric when the plane is known,
  // else in the frontal image, where a tilt foreshortens the cell. Only steps that shorten a
  // vector to below 0.8 are taken: a diagonal the spectrum chose is at least 1.3 bars long for
  // opening angles of 70-110 deg, while a side of a square seen at up to ~60 deg stays within 0.9
  // of the diagonal that could replace it, and a diamond's short diagonal is 1.06 bars at 117 deg
  // (hexagonal at 120: there bars and diagonal cannot be told apart).
  std::array<Eigen::Vector3d, 2> metric;
  if (normal_hint_C) {
    metric = bars_on_plane(out, camera, r, *normal_hint_C);
  } else {
    const Eigen::Matrix2d frontal = rot.topLeftCorner<2, 2>() * normalised(a);
    for (int i = 0; i < 2; ++i) metric[static_cast<size_t>(i)] << frontal.col(i), 0;
  }
  out.reduced = reduce_basis(a, metric, 0.8);
  if (metric[0].dot(metric[1]) < 0) a.col(1) = -a.col(1);
  out.lattice1_px = a.col(0);
  out.lattice2_px = a.col(1);
  if (a.col(0).norm() < params.min_period_px || a.col(1).norm() < params.min_period_px) {
    out.status = RoiStatus::kTooFine;
    return out;
  }
  const double acute = std::min(mesh.opening_angle_rad, std::numbers::pi - mesh.opening_angle_rad);
  Eigen::Matrix2d cell;
  cell << 1, std::cos(acute), 0, std::sin(acute);
  const Eigen::Matrix2d bv =
      rot.topLeftCorner<2, 2>() * normalised(a) * cell.inverse() / (r.norm() * mesh.bar_length_m);
  const Eigen::JacobiSVD<Eigen::Matrix2d> svd(bv, Eigen::ComputeFullU);
  const double s_max = svd.singularValues()(0), s_min = svd.singularValues()(1);
  if (!(s_max > 0) || !(1 / s_max <= params.max_range_m)) {
    out.status = RoiStatus::kBadGeometry;
    return out;
  }
  out.tilt_rad = std::acos(std::clamp(s_min / s_max, 0.0, 1.0));
  if (out.tilt_rad > params.max_tilt_rad) {
    out.status = RoiStatus::kTooOblique;
    return out;
  }
  out.range_m = 1 / s_max;
  out.p_C = out.range_m * r.normalized();
  const Eigen::Vector2d u_min = svd.matrixU().col(1);
  for (int s = 0; s < 2; ++s) {
    const double sign = s == 0 ? 1.0 : -1.0;
    const Eigen::Vector3d n_virtual(sign * std::sin(out.tilt_rad) * u_min.x(),
                                    sign * std::sin(out.tilt_rad) * u_min.y(),
                                    std::cos(out.tilt_rad));
    out.normals_C[s] = rot.transpose() * n_virtual;
  }
  out.status = RoiStatus::kValid;
  return out;
}

}  // namespace pensight
