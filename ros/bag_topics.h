#pragma once
// Which bag topic carries which sensor (docs/ros.md). Each role has the topic a typical ROS 1
// driver publishes on; a TOPICS.yaml file maps roles to other topic names.
#include <filesystem>
#include <string>

namespace pensight {

struct BagTopics {
  std::string image = "/camera/image_raw";                        // sensor_msgs/Image
  std::string image_compressed = "/camera/image_raw/compressed";  // sensor_msgs/CompressedImage
  std::string camera_info = "/camera/camera_info";                // sensor_msgs/CameraInfo
  std::string dvl_twist = "/dvl/twist";    // geometry_msgs/TwistWithCovarianceStamped
  std::string dvl_ranges = "/dvl/ranges";  // std_msgs/Float64MultiArray, 4 beam ranges
  std::string pressure = "/pressure";      // sensor_msgs/FluidPressure
  std::string imu = "/imu/data";           // sensor_msgs/Imu
};

// TOPICS.yaml: a mapping role -> topic name (`pressure: /bar30/pressure`) for any of the roles
// image, image_compressed, camera_info, dvl_twist, dvl_ranges, pressure, imu; the roles it does
// not name keep their defaults. Read strictly: throws pensight::Error naming the file and the key
// for a role that does not exist (a typo), a value that is not a non-empty string, or a file that
// is missing or not a YAML mapping.
BagTopics read_bag_topics(const std::filesystem::path& file);

}  // namespace pensight
