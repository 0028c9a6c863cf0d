#include "tests/ros/dataset_to_bag.h"

#include <rosbag/bag.h>

#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>

#include "ros/ros_frames.h"
#include "ros/ros_messages_detail.h"

namespace pensight::testing {
namespace {

ros::Time stamp(int64_t timestamp_ns) {
  ros::Time t;
  t.fromNSec(static_cast<uint64_t>(timestamp_ns));
  return t;
}

void write_frame(rosbag::Bag& bag, const BagWriteOptions& o, int64_t t_ns, const ImageU8& grey) {
  if (o.image_encoding == "png") {
    msg::CompressedImage m;
    m.header.stamp = stamp(t_ns);
    m.format = "png";
    std::vector<uchar> bytes;
    cv::imencode(
        ".png", cv::Mat(grey.height, grey.width, CV_8UC1, const_cast<uint8_t*>(grey.pixels.data())),
        bytes);
    m.data.assign(bytes.begin(), bytes.end());
    bag.write(o.topics.image_compressed, m.header.stamp, m);
    return;
  }
  msg::Image m;
  m.header.stamp = stamp(t_ns);
  m.width = static_cast<uint32_t>(grey.width);
  m.height = static_cast<uint32_t>(grey.height);
  m.encoding.assign(o.image_encoding.begin(), o.image_encoding.end());
  const size_t channels = o.image_encoding == "mono8" ? 1 : 3;  // grey in every channel
  m.step = static_cast<uint32_t>(grey.width * channels);
  for (const uint8_t g : grey.pixels) m.data.insert(m.data.end(), channels, g);
  bag.write(o.topics.image, m.header.stamp, m);
}

void write_camera_info(rosbag::Bag& bag, const BagWriteOptions& o, int64_t t_ns,
                       const PinholeCamera& c) {
  msg::CameraInfo m;
  m.header.stamp = stamp(t_ns);
  m.width = static_cast<uint32_t>(c.width_px);
  m.height = static_cast<uint32_t>(c.height_px);
  m.distortion_model = "plumb_bob";
  m.D = {c.k1, c.k2, c.p1, c.p2, 0.0};
  m.K = {c.fx_px, 0, c.cx_px, 0, c.fy_px, c.cy_px, 0, 0, 1};
  bag.write(o.topics.camera_info, m.header.stamp, m);
}

}  // namespace

void dataset_to_bag(const Dataset& d, const std::filesystem::path& file, const BagWriteOptions& o) {
  rosbag::Bag bag(file.string(), rosbag::bagmode::Write);
  // camera_info with every frame, as camera drivers publish it: a subscriber that connects after
  // the first frame still learns the calibration.
  for (size_t i = 0; i < d.frames.size(); ++i) {
    if (o.camera_info) write_camera_info(bag, o, d.frames[i].timestamp_ns, d.cam0.camera);
    write_frame(bag, o, d.frames[i].timestamp_ns, d.load_frame(i));
  }
  if (d.dvl0) {
    for (const DvlSample& s : d.dvl0->samples) {
      msg::TwistWithCovarianceStamped twist;
      twist.header.stamp = stamp(s.timestamp_ns);
      const Eigen::Vector3d v = s.valid ? s.velocity_B_mps : Eigen::Vector3d::Constant(kNaN);
      twist.twist.twist.linear.x = v.x();
      twist.twist.twist.linear.y = v.y();
      twist.twist.twist.linear.z = v.z();
      bag.write(o.topics.dvl_twist, twist.header.stamp, twist);
      if (!d.dvl0->has_beam_ranges) continue;
      msg::Float64MultiArray ranges;
      ranges.data.assign(s.beam_range_m.begin(), s.beam_range_m.end());
      bag.write(o.topics.dvl_ranges, twist.header.stamp, ranges);
    }
  }
  if (d.pressure0) {
    for (const PressureSample& s : *d.pressure0) {
      msg::FluidPressure m;
      m.header.stamp = stamp(s.timestamp_ns);
      m.fluid_pressure = pressure_from_depth_pa(s.depth_m, o.water);
      bag.write(o.topics.pressure, m.header.stamp, m);
    }
  }
  if (d.imu0) {
    for (const AttitudeSample& s : *d.imu0) {
      msg::Imu m;
      m.header.stamp = stamp(s.timestamp_ns);
      const Eigen::Quaterniond q =
          ros_orientation_from_pen_body(rotation_from_rpy(s.roll_rad, s.pitch_rad, s.yaw_rad));
      m.orientation.w = q.w();
      m.orientation.x = q.x();
      m.orientation.y = q.y();
      m.orientation.z = q.z();
      bag.write(o.topics.imu, m.header.stamp, m);
    }
  }
}

}  // namespace pensight::testing
