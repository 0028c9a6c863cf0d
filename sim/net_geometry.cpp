#include "sim/net_geometry.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "sim/net_mesh.h"

namespace pensight::sim {

namespace {

double circumference(const PenConfig& pen) {
  return pen.shape == NetShape::kCylinder ? 2 * std::numbers::pi * pen.radius_m : 0;
}

// The fold's surface length over the wall's under it, from its line to `x` (signed, clamped to
// the fold), on a wall of curvature `inv_radius` (0 on the plane). Per unit of along, the folded
// surface runs sqrt(k^2 + g^2): k = 1 - displacement / R, the radius the net is pushed to, g its
// slope. Both sides of the line are mirror images, so half the fold's extra lies on either side,
// and on each side k is linear and g constant: one Simpson panel is exact to 1e-9 of the length.
double fold_extra_from_line(const Bulge& b, double x, double inv_radius) {
  const double r = b.radius_m, g2 = (b.amplitude_m / r) * (b.amplitude_m / r);
  auto extra = [&](double at) {
    const double k = 1 - b.amplitude_m * (1 - std::abs(at) / r) * inv_radius;
    return std::sqrt(k * k + g2) - 1;
  };
  x = std::clamp(x, -r, r);
  return x / 6 * (extra(0) + 4 * extra(x / 2) + extra(x));
}

}  // namespace

double wrapped_along_offset(double along_m, double centre_m, double circumference_m) {
  const double d = along_m - centre_m;
  if (circumference_m <= 0) return d;
  return d - circumference_m * std::round(d / circumference_m);
}

NetGeometry::NetGeometry(const PenConfig& pen, const NetConfig& net)
    : pen_(pen), net_(net), fouling_cell_u_(net.fouling_scale_m) {
  double c = circumference(pen);
  // The folds' net runs once around the pen as well: u spans the circumference and their extra.
  for (const Bulge& b : net.bulges) {
    if (c > 0 && b.fold) c += 2 * fold_extra_from_line(b, b.radius_m, 1 / pen.radius_m);
  }
  if (c > 0) {
    // A whole number of the lattice's closing steps around the pen (net_mesh.h): the
    // undeformed mesh closes exactly for every mesh type and opening angle.
    const double step = NetLattice::closing_step(net);
    lattice_scale_ = std::max(1.0, std::round(c / step)) * step / c;
    fouling_cells_ =
        static_cast<int>(std::max(1.0, std::round(c * lattice_scale_ / net.fouling_scale_m)));
    fouling_cell_u_ = c * lattice_scale_ / fouling_cells_;
    u_around_ = c * lattice_scale_;
  }
}

double NetGeometry::fold_arc_offset(double along_m) const {
  const double inv_radius = pen_.shape == NetShape::kCylinder ? 1 / pen_.radius_m : 0;
  double offset = 0;
  for (const Bulge& b : net_.bulges) {
    if (b.fold) offset += fold_extra_from_line(b, along_m - b.along_m, inv_radius);
  }
  return offset;
}

double NetGeometry::displacement(double along_m, double depth_m) const {
  const double c = circumference(pen_);
  double sum = 0;
  for (const Bulge& b : net_.bulges) {
    const double da = wrapped_along_offset(along_m, b.along_m, c), dz = depth_m - b.depth_m;
    sum += b.fold ? b.amplitude_m * std::max(0.0, 1 - std::abs(da) / b.radius_m)
                  : b.amplitude_m * std::exp(-(da * da + dz * dz) / (2 * b.radius_m * b.radius_m));
  }
  return sum;
}

Eigen::Vector2d NetGeometry::displacement_gradient(double along_m, double depth_m) const {
  const double c = circumference(pen_);
  Eigen::Vector2d g = Eigen::Vector2d::Zero();
  for (const Bulge& b : net_.bulges) {
    const double da = wrapped_along_offset(along_m, b.along_m, c), dz = depth_m - b.depth_m,
                 s2 = b.radius_m * b.radius_m;
    if (b.fold) {
      if (std::abs(da) < b.radius_m) g.x() -= (da > 0 ? 1 : -1) * b.amplitude_m / b.radius_m;
      continue;
    }
    const double e = b.amplitude_m * std::exp(-(da * da + dz * dz) / (2 * s2));
    g += Eigen::Vector2d(-da / s2 * e, -dz / s2 * e);
  }
  return g;
}

double NetGeometry::along_of(const Eigen::Vector3d& p) const {
  return pen_.shape == NetShape::kPlane ? p.y() : pen_.radius_m * std::atan2(p.y(), p.x());
}

double NetGeometry::clearance(const Eigen::Vector3d& p) const {
  const double surface = pen_.radius_m - displacement(along_of(p), p.z());
  return surface - (pen_.shape == NetShape::kPlane ? p.x() : std::hypot(p.x(), p.y()));
}

std::optional<NetHit> NetGeometry::intersect_wall_or_plane(const Eigen::Vector3d& o,
                                                           const Eigen::Vector3d& d) const {
  const double R = pen_.radius_m;
  double offset = 0, t = -1, along = 0, disp = 0;
  Eigen::Vector3d p;
  for (int i = 0; i < kBulgeIterations; ++i) {
    const double r = R - offset;
    if (pen_.shape == NetShape::kPlane) {
      if (!(d.x() > 0)) return std::nullopt;
      t = (r - o.x()) / d.x();
    } else {
      // |o_xy + t d_xy| = r, the far root (the camera is inside the cylinder).
      const double a = d.x() * d.x() + d.y() * d.y();
      if (a < 1e-12) return std::nullopt;
      const double b = o.x() * d.x() + o.y() * d.y();
      const double c = o.x() * o.x() + o.y() * o.y() - r * r;
      const double disc = b * b - a * c;
      if (disc < 0) return std::nullopt;
      t = (-b + std::sqrt(disc)) / a;
    }
    if (!(t > 0)) return std::nullopt;
    p = o + t * d;
    along = along_of(p);
    if (net_.bulges.empty()) break;
    disp = displacement(along, p.z());
    if (std::abs(disp - offset) < kBulgeTolerance_m) break;
    offset = disp;
  }
  NetHit h;
  h.t = t;
  h.point = p;
  const Eigen::Vector2d g = displacement_gradient(along, p.z());
  h.u_m = (along + fold_arc_offset(along)) * lattice_scale_;
  h.v_m = p.z();
  h.tangent_v = Eigen::Vector3d::UnitZ();
  if (pen_.shape == NetShape::kPlane) {
    h.part = NetPart::kPlane;
    h.tangent_u = Eigen::Vector3d::UnitY();
    h.normal = Eigen::Vector3d(1, g.x(), g.y()).normalized();
  } else {
    h.part = NetPart::kWall;
    const Eigen::Vector3d e_r = Eigen::Vector3d(p.x(), p.y(), 0).normalized();
    const Eigen::Vector3d e_t(-e_r.y(), e_r.x(), 0);
    const double k = (R - disp) / R;
    h.tangent_u = lattice_scale_ * e_t;
    // Cross product of the surface's along and depth derivatives (see docs/sim.md).
    h.normal = (k * e_r + g.x() * e_t + k * g.y() * Eigen::Vector3d::UnitZ()).normalized();
  }
  return h;
}

std::optional<NetHit> NetGeometry::intersect(const Eigen::Vector3d& o,
                                             const Eigen::Vector3d& d) const {
  auto hit = intersect_wall_or_plane(o, d);
  if (pen_.shape == NetShape::kPlane) {
    if (!hit) return std::nullopt;
    const Eigen::Vector3d& p = hit->point;
    if (std::abs(p.y()) > pen_.width_m / 2 || p.z() < pen_.top_m ||
        p.z() > pen_.top_m + pen_.height_m) {
      return std::nullopt;
    }
    return hit;
  }
  if (hit && hit->point.z() <= pen_.depth_m) return hit;
  if (!pen_.bottom || !(d.z() > 0)) return std::nullopt;
  const double t = (pen_.depth_m - o.z()) / d.z();
  if (!(t > 0)) return std::nullopt;
  NetHit b;
  b.t = t;
  b.point = o + t * d;
  if (b.point.head<2>().norm() > pen_.radius_m) return std::nullopt;
  b.normal = Eigen::Vector3d::UnitZ();
  b.u_m = b.point.x();
  b.v_m = b.point.y();
  b.tangent_u = Eigen::Vector3d::UnitX();
  b.tangent_v = Eigen::Vector3d::UnitY();
  b.part = NetPart::kBottom;
  return b;
}

std::optional<double> NetGeometry::intersect_wall(const Eigen::Vector3d& o,
                                                  const Eigen::Vector3d& d) const {
  if (pen_.shape != NetShape::kPlane || pen_.wall_gap_m <= 0 || !(d.x() > 0)) return std::nullopt;
  const double t = (pen_.radius_m + pen_.wall_gap_m - o.x()) / d.x();
  return t > 0 ? std::optional<double>(t) : std::nullopt;
}

}  // namespace pensight::sim
