#include "apps/ros/node_messages.h"

#include <Eigen/Geometry>

#include <cmath>
#include <cstring>

#include "core/units.h"
#include "pipeline/fft/relative_pose_fft.h"

namespace pensight::node {
namespace {

// FRD body axes -> REP 103's FLU base_link: y and z flip.
const Eigen::Matrix3d kR_frd_flu = Eigen::Vector3d(1, -1, -1).asDiagonal();

template <class Pose>
void set_pose(Pose& out, const Eigen::Vector3d& t, const Eigen::Quaterniond& q) {
  out.position.x = t.x(), out.position.y = t.y(), out.position.z = t.z();
  out.orientation.w = q.w(), out.orientation.x = q.x(), out.orientation.y = q.y();
  out.orientation.z = q.z();
}

bool finite(const Eigen::Isometry3d& T) {
  return T.matrix().allFinite();
}

}  // namespace

msg::Header header(int64_t stamp_ns, const std::string& frame_id) {
  msg::Header h;
  h.stamp.fromNSec(static_cast<uint64_t>(stamp_ns));
  h.frame_id = frame_id;
  return h;
}

msg::PointCloud2 point_cloud(const msg::Header& h, const std::vector<std::string>& fields,
                             const std::vector<std::vector<float>>& rows) {
  msg::PointCloud2 c;
  c.header = h;
  c.height = 1;
  c.width = static_cast<uint32_t>(rows.size());
  for (size_t i = 0; i < fields.size(); ++i) {
    c.fields.emplace_back();
    c.fields.back().name = fields[i];
    c.fields.back().offset = static_cast<uint32_t>(4 * i);
    c.fields.back().datatype = sensor_msgs::PointField_<msg::RosAllocator<void>>::FLOAT32;
    c.fields.back().count = 1;
  }
  c.is_bigendian = false;
  c.point_step = static_cast<uint32_t>(4 * fields.size());
  c.row_step = c.point_step * c.width;
  c.is_dense = true;
  c.data.resize(c.row_step);
  for (size_t r = 0; r < rows.size(); ++r) {
    std::memcpy(c.data.data() + r * c.point_step, rows[r].data(), c.point_step);
  }
  return c;
}

msg::PointCloud2 net_points_cloud(const NetDetection& d, const msg::Header& h) {
  std::vector<std::vector<float>> rows;
  for (const RoiNetPoint& p : d.points) {
    if (p.status != RoiStatus::kValid || !p.p_C.allFinite()) continue;
    rows.push_back({static_cast<float>(p.p_C.x()), static_cast<float>(p.p_C.y()),
                    static_cast<float>(p.p_C.z()), static_cast<float>(p.quality)});
  }
  return point_cloud(h, {"x", "y", "z", "quality"}, rows);
}

msg::PointCloud2 sparse_depth_cloud(const NetDetection& d, const PinholeCamera& camera,
                                    const msg::Header& h) {
  std::vector<std::vector<float>> rows;
  for (const SparseDepth& s : d.depths) {
    const Eigen::Vector3d p_C = s.point.depth_m * camera.ray({s.point.x_px, s.point.y_px});
    rows.push_back({static_cast<float>(p_C.x()), static_cast<float>(p_C.y()),
                    static_cast<float>(p_C.z()), s.point.x_px, s.point.y_px, s.point.depth_m,
                    s.quality});
  }
  return point_cloud(h, {"x", "y", "z", "u", "v", "depth", "quality"}, rows);
}

msg::PoseStamped relative_pose(const FftRelativePose& pose, const msg::Header& h) {
  msg::PoseStamped out;
  out.header = h;
  if (!pose.valid()) {
    set_pose(out.pose, Eigen::Vector3d::Constant(kNaN), Eigen::Quaterniond(kNaN, kNaN, kNaN, kNaN));
    return out;
  }
  // net_plane_normal points at the camera; the net frame's z points away from it.
  const Eigen::Vector3d z =
      -net_plane_normal(std::tan(pose.psi_net_rad), std::tan(pose.pitch_net_rad)).normalized();
  const Eigen::Vector3d x = Eigen::Vector3d::UnitY().cross(z).normalized();
  Eigen::Matrix3d R;
  R << x, z.cross(x), z;
  set_pose(out.pose, Eigen::Vector3d(0, 0, pose.d_net_m), Eigen::Quaterniond(R));
  return out;
}

msg::PoseWithCovarianceStamped global_pose(const global_pose::GlobalPose& g, const msg::Header& h) {
  msg::PoseWithCovarianceStamped out;
  out.header = h;
  const Eigen::Isometry3d& T = g.T_pen_body;
  set_pose(out.pose.pose, T.translation(), Eigen::Quaterniond(T.linear() * kR_frd_flu));
  // (x, y, z, roll, pitch, yaw) from (r, rho, z, psi): x = r cos rho, y = r sin rho.
  Eigen::Matrix<double, 6, 4> J = Eigen::Matrix<double, 6, 4>::Zero();
  J(0, 0) = std::cos(g.rho_g_rad), J(0, 1) = -g.r_g_m * std::sin(g.rho_g_rad);
  J(1, 0) = std::sin(g.rho_g_rad), J(1, 1) = g.r_g_m * std::cos(g.rho_g_rad);
  J(2, 2) = 1;
  J(5, 3) = 1;
  Eigen::Matrix<double, 6, 6> C = J * g.covariance * J.transpose();
  C(3, 3) = C(4, 4) = kAttitudeVariance_rad2;
  for (int r = 0; r < 6; ++r)
    for (int c = 0; c < 6; ++c) out.pose.covariance[6 * r + c] = C(r, c);
  return out;
}

namespace {

msg::TFMessage transform(const Eigen::Isometry3d& T_parent_child, int64_t stamp_ns,
                         const std::string& parent, const std::string& child) {
  msg::TFMessage out;
  out.transforms.emplace_back();
  auto& t = out.transforms.back();
  t.header = header(stamp_ns, parent);
  t.child_frame_id = child;
  const Eigen::Vector3d p = T_parent_child.translation();
  const Eigen::Quaterniond q(T_parent_child.linear());
  t.transform.translation.x = p.x(), t.transform.translation.y = p.y();
  t.transform.translation.z = p.z();
  t.transform.rotation.w = q.w(), t.transform.rotation.x = q.x(), t.transform.rotation.y = q.y();
  t.transform.rotation.z = q.z();
  return out;
}

}  // namespace

msg::TFMessage pen_to_base_link(const global_pose::GlobalPose& g, int64_t stamp_ns,
                                const std::string& pen_frame, const std::string& base_frame) {
  if (!finite(g.T_pen_body)) return {};
  Eigen::Isometry3d T_pen_base = g.T_pen_body;
  T_pen_base.linear() = g.T_pen_body.linear() * kR_frd_flu;
  return transform(T_pen_base, stamp_ns, pen_frame, base_frame);
}

msg::TFMessage base_link_to_camera(const Eigen::Isometry3d& T_body_camera, int64_t stamp_ns,
                                   const std::string& base_frame, const std::string& camera_frame) {
  Eigen::Isometry3d T_base_camera = T_body_camera;
  T_base_camera.translation() = kR_frd_flu.transpose() * T_body_camera.translation();
  T_base_camera.linear() = kR_frd_flu.transpose() * T_body_camera.linear();
  return transform(T_base_camera, stamp_ns, base_frame, camera_frame);
}

msg::Image depth_image(const ImageF32& depth_m, const msg::Header& h) {
  msg::Image out;
  out.header = h;
  out.width = static_cast<uint32_t>(depth_m.width);
  out.height = static_cast<uint32_t>(depth_m.height);
  out.encoding = "32FC1";
  out.is_bigendian = false;
  out.step = 4 * out.width;
  out.data.resize(static_cast<size_t>(out.step) * out.height);
  std::memcpy(out.data.data(), depth_m.pixels.data(), out.data.size());
  return out;
}

msg::PointCloud2 map_cloud(const std::vector<Eigen::Vector3f>& centres_pen, const msg::Header& h) {
  std::vector<std::vector<float>> rows;
  rows.reserve(centres_pen.size());
  for (const Eigen::Vector3f& p : centres_pen) rows.push_back({p.x(), p.y(), p.z()});
  return point_cloud(h, {"x", "y", "z"}, rows);
}

}  // namespace pensight::node
