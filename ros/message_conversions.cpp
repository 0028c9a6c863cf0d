#include "ros/message_conversions_detail.h"

#include <algorithm>
#include <cmath>
#include <vector>

#include "core/error.h"
#include "core/image.h"
#include "core/units.h"
#include "pipeline/dataset/sensor_mounts.h"
#include "ros/image_decoding.h"
#include "ros/ros_frames.h"

namespace pensight {

int64_t to_ns(const ros::Time& t) {
  return static_cast<int64_t>(t.toNSec());
}

CameraCalibration camera_from_info(const msg::CameraInfo& info, const std::string& topic,
                                   const std::string& fix) {
  const auto fail = [&](const std::string& what) {
    throw Error("topic '" + topic + "': " + what + "; " + fix);
  };
  constexpr auto kMaxSide = static_cast<uint32_t>(kMaxImageSide_px);
  if (info.width == 0 || info.height == 0 || info.width > kMaxSide || info.height > kMaxSide) {
    fail("image size " + std::to_string(info.width) + "x" + std::to_string(info.height) +
         " (1 to " + std::to_string(kMaxSide) + " px per side)");
  }
  const auto& K = info.K;  // row-major 3x3
  const bool pinhole = K[1] == 0 && K[3] == 0 && K[6] == 0 && K[7] == 0 && K[8] == 1 && K[0] > 0 &&
                       K[4] > 0 && std::isfinite(K[0] + K[2] + K[4] + K[5]);
  if (!pinhole) fail("K is not a pinhole matrix [fx 0 cx; 0 fy cy; 0 0 1] with fx, fy > 0");
  if (info.binning_x > 1 || info.binning_y > 1 ||
      (info.roi.width != 0 && (info.roi.width != info.width || info.roi.height != info.height))) {
    fail("binning and regions of interest are not supported");
  }
  // plumb_bob is OpenCV's k1, k2, p1, p2, k3; the contract's radial-tangential has no k3.
  const std::string model = msg::to_std_string(info.distortion_model);
  const std::vector<double> D(info.D.begin(), info.D.end());
  const bool no_distortion = std::all_of(D.begin(), D.end(), [](double d) { return d == 0; });
  if (!no_distortion && model != "plumb_bob") {
    fail("distortion model '" + model + "' is not supported (plumb_bob is)");
  }
  if (!no_distortion &&
      (D.size() < 4 || D.size() > 5 || (D.size() == 5 && D[4] != 0) ||
       !std::all_of(D.begin(), D.end(), [](double d) { return std::isfinite(d); }))) {
    fail(
        "plumb_bob distortion needs D = [k1, k2, p1, p2] or [k1, k2, p1, p2, 0] (the contract's "
        "radial-tangential model has no k3)");
  }
  CameraCalibration c;
  c.camera.width_px = static_cast<int>(info.width);
  c.camera.height_px = static_cast<int>(info.height);
  c.camera.fx_px = K[0];
  c.camera.fy_px = K[4];
  c.camera.cx_px = K[2];
  c.camera.cy_px = K[5];
  if (!no_distortion) {
    c.camera.k1 = D[0], c.camera.k2 = D[1], c.camera.p1 = D[2], c.camera.p2 = D[3];
  }
  c.T_body_camera = forward_mount(Eigen::Vector3d::Zero(), 0, 0);
  return c;
}

DvlCalibration default_dvl_calibration(double rate_hz) {
  return janus_dvl_calibration(rate_hz, forward_mount(Eigen::Vector3d::Zero(), 0, 0),
                               deg_to_rad(25));
}

DvlSample dvl_sample_from_twist(const msg::TwistWithCovarianceStamped& m) {
  const auto& v = m.twist.twist.linear;
  DvlSample s;
  s.timestamp_ns = to_ns(m.header.stamp);
  s.valid = std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
  s.velocity_B_mps = s.valid ? Eigen::Vector3d(v.x, v.y, v.z) : Eigen::Vector3d::Constant(kNaN);
  return s;
}

std::array<double, 4> beam_ranges_from(const msg::Float64MultiArray& m, std::string& problem) {
  std::array<double, 4> range_m{kNaN, kNaN, kNaN, kNaN};
  if (m.data.size() != 4) {
    problem =
        "has " + std::to_string(m.data.size()) + " values; dvl_ranges takes the 4 beam ranges [m]";
    return range_m;
  }
  for (size_t k = 0; k < 4; ++k) {
    if (std::isfinite(m.data[k]) && m.data[k] > 0) range_m[k] = m.data[k];
  }
  return range_m;
}

PressureSample pressure_sample_from(const msg::FluidPressure& m, const WaterColumn& water,
                                    std::string& problem) {
  if (!std::isfinite(m.fluid_pressure)) problem = "fluid_pressure is not finite";
  return {to_ns(m.header.stamp), depth_from_pressure_m(m.fluid_pressure, water)};
}

AttitudeSample attitude_sample_from(const msg::Imu& m, std::string& problem) {
  const auto& o = m.orientation;
  const Eigen::Quaterniond q(o.w, o.x, o.y, o.z);
  // sensor_msgs/Imu: orientation_covariance[0] = -1 says the message has no orientation.
  if (m.orientation_covariance[0] == -1) {
    problem = "orientation_covariance[0] is -1: no orientation";
  } else if (!(std::abs(q.norm() - 1) < 1e-3)) {
    problem = "orientation is not a unit quaternion";
  }
  if (!problem.empty()) return {to_ns(m.header.stamp), kNaN, kNaN, kNaN};
  const Eigen::Vector3d rpy = rpy_from_rotation(rotation_pen_body_from_ros(q.normalized()));
  return {to_ns(m.header.stamp), rpy.x(), rpy.y(), rpy.z()};
}

ImageU8 grey_from(const msg::Image& m, const std::string& topic) {
  return grey_from_raw_image(m.width, m.height, m.step, msg::to_std_string(m.encoding), m.data,
                             topic);
}

ImageU8 grey_from(const msg::CompressedImage& m, int width_px, int height_px,
                  const std::string& topic) {
  return grey_from_compressed_image(msg::to_std_string(m.format), m.data, width_px, height_px,
                                    topic);
}

}  // namespace pensight
