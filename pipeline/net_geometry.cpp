#include "pipeline/net_geometry.h"

#include <Eigen/Geometry>
#include <Eigen/SVD>
#include <algorithm>
#include <cmath>
#include <string>

#include "runtime/error.h"

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

RoiNetPoint roi_net_point(const kernels::RoiLattice& lattice, kernels::RoiOrigin origin,
                          int roi_size, const PinholeCamera& camera, double mesh_m,
                          const NetPointParams& params) {
  if (!(mesh_m > 0)) {
    throw Error("roi_net_point: net mesh size must be > 0 m, got " + std::to_string(mesh_m) +
                "; set net_mesh_size_m in scene.yaml");
  }
  RoiNetPoint out;
  out.quality = lattice.quality;
  // The lattice was measured where the ROI's energy is: on the net part of a ROI at its edge.
  out.centre_px = Eigen::Vector2d(origin.x + 0.5 * (roi_size - 1), origin.y + 0.5 * (roi_size - 1));
  if (params.use_centroid)
    out.centre_px += Eigen::Vector2d(lattice.centroid_dx, lattice.centroid_dy);
  if (!(lattice.quality >= params.min_quality)) return out;
  if (std::hypot(lattice.centroid_dx, lattice.centroid_dy) > params.max_centroid_share * roi_size) {
    out.status = RoiStatus::kPartial;
    return out;
  }

  Eigen::Matrix2d f;
  f << lattice.f1x, lattice.f2x, lattice.f1y, lattice.f2y;
  if (!(std::abs(f.determinant()) > 1e-12)) {
    out.status = RoiStatus::kBadGeometry;
    return out;
  }
  const Eigen::Matrix2d a = f.inverse().transpose();  // a_i . f_j = delta_ij
  out.lattice1_px = a.col(0);
  out.lattice2_px = a.col(1);
  if (a.col(0).norm() < params.min_period_px || a.col(1).norm() < params.min_period_px) {
    out.status = RoiStatus::kTooFine;
    return out;
  }

  // Lattice vectors in the normalised, undistorted image (central differences through ray()).
  const Eigen::Vector3d r = camera.ray(out.centre_px);
  Eigen::Matrix2d b;
  for (int i = 0; i < 2; ++i) {
    const Eigen::Vector2d h = 0.5 * a.col(i);
    b.col(i) = (camera.ray(out.centre_px + h) - camera.ray(out.centre_px - h)).head<2>();
  }
  // Virtual rotation R taking the centre ray onto +z; its image Jacobian there is R_2x2 / |r|.
  const Eigen::Matrix3d rot =
      Eigen::Quaterniond::FromTwoVectors(r.normalized(), Eigen::Vector3d::UnitZ())
          .toRotationMatrix();
  const Eigen::Matrix2d bv = rot.topLeftCorner<2, 2>() * b / (r.norm() * mesh_m);
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
