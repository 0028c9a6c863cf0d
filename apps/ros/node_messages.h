#pragma once
// What pensight_node publishes, built from one FrameResult (pipeline.h) and stamped with the
// camera's time. Frames (docs/ros.md): the camera frame is C (OpenCV: x right, y down, z
// forward, as a ROS optical frame); the pen frame is P (z down, dataset-format.md); base_link is
// the body in REP 103's FLU, so T_pen_base_link = T_pen_body * R_frd_flu.
// Implementation-only: names ROS types.
#include <geometry_msgs/PoseStamped.h>
#include <geometry_msgs/PoseWithCovarianceStamped.h>
#include <sensor_msgs/PointCloud2.h>
#include <std_msgs/Float64.h>
#include <tf2_msgs/TFMessage.h>

#include <Eigen/Core>

#include <string>
#include <vector>

#include "core/camera.h"
#include "pipeline/pipeline.h"
#include "ros/ros_messages_detail.h"

namespace pensight::node {

namespace msg {
using pensight::msg::RosAllocator;
using Float64 = std_msgs::Float64_<RosAllocator<void>>;
using Header = std_msgs::Header_<RosAllocator<void>>;
using PointCloud2 = sensor_msgs::PointCloud2_<RosAllocator<void>>;
using PoseStamped = geometry_msgs::PoseStamped_<RosAllocator<void>>;
using PoseWithCovarianceStamped = geometry_msgs::PoseWithCovarianceStamped_<RosAllocator<void>>;
using TFMessage = tf2_msgs::TFMessage_<RosAllocator<void>>;
using Image = pensight::msg::Image;
}  // namespace msg

msg::Header header(int64_t stamp_ns, const std::string& frame_id);

// One float32 field per name, one point per row (every row as long as `fields`), unorganised.
msg::PointCloud2 point_cloud(const msg::Header& h, const std::vector<std::string>& fields,
                             const std::vector<std::vector<float>>& rows);

// ~net_points: each ROI's net point in C (x, y, z, quality), the ROIs with a usable lattice.
msg::PointCloud2 net_points_cloud(const NetDetection& d, const msg::Header& h);
// ~sparse_depth: the depth priors (x, y, z in C; u, v in camera pixels; depth z [m]; quality).
msg::PointCloud2 sparse_depth_cloud(const NetDetection& d, const PinholeCamera& camera,
                                    const msg::Header& h);

// ~relative_pose in C: the net point on the optical axis (0, 0, d_net) and the net frame's
// orientation (its z along the net normal away from the camera, its x in C's x-z plane); NaN
// position and orientation when the FFT pose is not valid.
msg::PoseStamped relative_pose(const FftRelativePose& pose, const msg::Header& h);

// ~global_pose in P: T_pen_base_link with the covariance of (x, y, z, roll, pitch, yaw) from the
// estimator's (r_g, rho_g, z_g, psi_g) covariance; roll and pitch, which the estimator takes as
// measured, carry kAttitudeVariance_rad2.
inline constexpr double kAttitudeVariance_rad2 = 3.0e-6;  // (0.1 deg)^2
msg::PoseWithCovarianceStamped global_pose(const global_pose::GlobalPose& g, const msg::Header& h);

// The tf pen -> base_link of a finite global pose.
msg::TFMessage pen_to_base_link(const global_pose::GlobalPose& g, int64_t stamp_ns,
                                const std::string& pen_frame, const std::string& base_frame);

// The static tf base_link -> camera of the camera's mount (T_body_camera, the body FRD).
msg::TFMessage base_link_to_camera(const Eigen::Isometry3d& T_body_camera, int64_t stamp_ns,
                                   const std::string& base_frame, const std::string& camera_frame);

// ~depth: z-depth [m] as 32FC1, NaN where there is no estimate.
msg::Image depth_image(const ImageF32& depth_m, const msg::Header& h);

// ~map: occupied voxel centres in P.
msg::PointCloud2 map_cloud(const std::vector<Eigen::Vector3f>& centres_pen, const msg::Header& h);

}  // namespace pensight::node
