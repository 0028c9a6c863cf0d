#include "sim/ground_truth.h"

#include <algorithm>
#include <cmath>

#include "core/net_angles.h"
#include "core/units.h"

namespace pensight::sim {

NetRelative net_relative(const Scenario& s, const NetGeometry& net,
                         const Eigen::Isometry3d& T_pen_camera) {
  NetRelative r;
  const Eigen::Vector3d o = T_pen_camera.translation();
  const Eigen::Vector3d d = T_pen_camera.linear().col(2);
  const auto hit = net.intersect(o, d);
  if (!hit || hit->t > net_visible_range_m(s.water)) return r;
  if (d.z() < 0 && -o.z() / d.z() <= hit->t) return r;  // the surface comes first
  r.d_net_m = hit->t;
  r.m_C = T_pen_camera.linear().transpose() * hit->normal;
  const NetAngles angles = net_angles_from_normal_C(r.m_C);
  r.psi_net_rad = angles.psi_rad;
  r.pitch_net_rad = angles.pitch_rad;
  return r;
}

MeshTruthRow mesh_truth_row(const Scenario& s, const NetGeometry& net, const NetLattice& lattice,
                            const FrameState& f) {
  MeshTruthRow row;
  row.timestamp_ns = f.timestamp_ns;
  row.mesh_type = s.net.mesh_type;
  if (std::isnan(net_relative(s, net, f.T_pen_camera).d_net_m)) return row;
  const auto hit = net.intersect(f.T_pen_camera.translation(), f.T_pen_camera.linear().col(2));
  const bool wall = hit->part == NetPart::kWall;
  const LocalMesh m =
      lattice.local_mesh(hit->u_m, hit->v_m, hit->part, wall ? net.lattice_scale() : 1.0);
  row.opening_angle_rad = m.opening_angle_rad;
  row.stretch = m.stretch;
  return row;
}

GroundTruthRow ground_truth_row(const Scenario& s, const NetGeometry& net, const FrameState& f,
                                const ImageF32& depth_m) {
  GroundTruthRow g;
  g.timestamp_ns = f.timestamp_ns;
  g.p_pen_body_m = f.body.T_pen_body.translation();
  g.roll_rad = f.body.roll_rad;
  g.pitch_rad = f.body.pitch_rad;
  g.yaw_rad = wrap_angle(f.body.yaw_rad);
  const NetRelative r = net_relative(s, net, f.T_pen_camera);
  g.d_net_m = r.d_net_m;
  g.psi_net_rad = r.psi_net_rad;
  g.pitch_net_rad = r.pitch_net_rad;
  const auto seen =
      std::count_if(depth_m.pixels.begin(), depth_m.pixels.end(), [](float z) { return z > 0; });
  g.net_fraction = depth_m.pixels.empty()
                       ? 0.0
                       : static_cast<double>(seen) / static_cast<double>(depth_m.pixels.size());
  return g;
}

}  // namespace pensight::sim
