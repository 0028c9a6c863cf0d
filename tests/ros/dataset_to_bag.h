#pragma once
// A dataset written as a ROS 1 bag, the inverse of bag_to_dataset (ros/bag_dataset.h), for
// round-trip tests: cam0 frames as sensor_msgs/Image (mono8, bgr8, rgb8) or CompressedImage (png),
// cam0/sensor.yaml as a sensor_msgs/CameraInfo with each frame, dvl0 as TwistWithCovarianceStamped
// (NaN velocity where invalid) and Float64MultiArray beam ranges, pressure0 as FluidPressure and
// imu0 as Imu orientations (ros/ros_frames.h). Every message's bag time is its stamp.
#include <filesystem>
#include <string>

#include "pipeline/dataset/dataset_reader.h"
#include "ros/bag_topics.h"
#include "ros/pressure_depth.h"

namespace pensight::testing {

struct BagWriteOptions {
  std::string image_encoding = "mono8";  // mono8 | bgr8 | rgb8 | png (a CompressedImage)
  bool camera_info = true;
  BagTopics topics;
  WaterColumn water;
};

// Writes `d` (frames loaded from its folder) to `bag`, replacing it.
void dataset_to_bag(const Dataset& d, const std::filesystem::path& bag,
                    const BagWriteOptions& options = {});

}  // namespace pensight::testing
