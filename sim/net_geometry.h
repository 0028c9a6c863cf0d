#pragma once
// Ray intersection with the net (cylinder wall with optional bottom, or a flat rectangle), with
// the smooth bulges of NetConfig. Shared by the CPU renderer, the ground truth and the DVL; the
// Vulkan shader (shaders/sim/render.comp) implements the same steps in float.
#include <Eigen/Core>
#include <optional>

#include "sim/scenario.h"

namespace pensight::sim {

enum class NetPart { kWall, kBottom, kPlane };

struct NetHit {
  double t = 0;             // distance along the unit ray
  Eigen::Vector3d point;    // in P
  Eigen::Vector3d normal;   // unit, pointing out of the pen (away from a camera inside it)
  double u_m = 0, v_m = 0;  // net surface coordinates: twine lines at multiples of bar_length_m
  // Directions of increasing u, v in P; |tangent| = du/ds per metre on the surface (1, except
  // the cylinder wall's u, which is stretched by NetGeometry::lattice_scale()).
  Eigen::Vector3d tangent_u, tangent_v;
  NetPart part = NetPart::kWall;
};

// Fixed-point steps for the bulged surface: each re-intersects the undeformed shape offset by
// the bulge displacement found at the previous hit, until the displacement changes by less than
// kBulgeTolerance_m (at most kBulgeIterations steps; slopes below ~0.5 converge well within).
inline constexpr int kBulgeIterations = 6;
inline constexpr double kBulgeTolerance_m = 1e-5;

class NetGeometry {
 public:
  NetGeometry(const PenConfig& pen, const NetConfig& net);

  // A fold's panels hold the net unstretched: across a fold the wall's u runs with the length of
  // the folded surface, longer than the wall's arc under it (by 5.4 % at the line of a valley
  // 0.35 m out and 1.5 m to either side on a 12 m pen: pushed out, the net is on a larger radius
  // as well as sloped), half of each fold's extra length on either side of its line. This is
  // that offset of u / lattice_scale() from along (0 without folds). A dent stretches its net,
  // as a current pushing on it does. Precondition: along_m in (-circumference / 2,
  // circumference / 2] and each fold at least its radius_m from that wrap (validate(Scenario)).
  double fold_arc_offset(double along_m) const;

  // Inward displacement of the net at (along, depth), and its derivatives d/dalong, d/ddepth.
  double displacement(double along_m, double depth_m) const;
  Eigen::Vector2d displacement_gradient(double along_m, double depth_m) const;

  // First net hit along origin + t * dir (dir unit), t > 0, below or above the water alike.
  std::optional<NetHit> intersect(const Eigen::Vector3d& origin, const Eigen::Vector3d& dir) const;
  // Basin wall behind a flat net (plane shape with wall_gap_m > 0).
  std::optional<double> intersect_wall(const Eigen::Vector3d& origin,
                                       const Eigen::Vector3d& dir) const;

  // Signed distance of p from the (bulged) net, measured along the pen's radius (cylinder) or x
  // (plane); positive inside the pen.
  double clearance(const Eigen::Vector3d& p) const;
  double along_of(const Eigen::Vector3d& p) const;

  // The cylinder wall's u = (along + fold_arc_offset(along)) * lattice_scale(): the
  // circumference and the folds' extra length hold a whole number of
  // meshes (and of fouling cells, fouling_cells_around()), so the twine pattern and the fouling
  // continue across the azimuth +-pi where along wraps. 1 on the plane; on a 12 m pen with a
  // 30 mm mesh it is 1 - 1.1e-4.
  double lattice_scale() const { return lattice_scale_; }
  int fouling_cells_around() const { return fouling_cells_; }
  // The wall's u once around the pen ((circumference + the folds' extra length) x
  // lattice_scale()); 0 on the plane.
  double u_around() const { return u_around_; }
  // Fouling cell size along u on the wall (fouling_scale_m, stretched to close the ring).
  double fouling_cell_u() const { return fouling_cell_u_; }

  const PenConfig& pen() const { return pen_; }
  const NetConfig& net() const { return net_; }

 private:
  std::optional<NetHit> intersect_wall_or_plane(const Eigen::Vector3d& o,
                                                const Eigen::Vector3d& d) const;
  PenConfig pen_;
  NetConfig net_;
  double lattice_scale_ = 1;
  int fouling_cells_ = 0;  // 0: no wrap (plane)
  double u_around_ = 0;
  double fouling_cell_u_ = 0;
};

// Along-distance from a bulge centre, wrapped onto the shorter way round on a cylinder of
// circumference `circumference_m` (0: plane, no wrap).
double wrapped_along_offset(double along_m, double centre_m, double circumference_m);

}  // namespace pensight::sim
