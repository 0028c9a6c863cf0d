#pragma once
// The ROS 1 message types pensight reads from bags (and its tests write), usable from C++20.
// Debian's generated message headers name std::allocator<void>::rebind, which C++20 removed, so
// the messages are instantiated with RosAllocator: std::allocator with that member. A message's
// type name, MD5 sum and wire format do not depend on its allocator, so bags recorded by ROS read
// with these types and bags written with them read in ROS.
// Implementation-only (not installed): the ROS headers stay out of the layer's public interface.
#include <geometry_msgs/TwistWithCovarianceStamped.h>
#include <sensor_msgs/CameraInfo.h>
#include <sensor_msgs/CompressedImage.h>
#include <sensor_msgs/FluidPressure.h>
#include <sensor_msgs/Image.h>
#include <sensor_msgs/Imu.h>
#include <std_msgs/Float64MultiArray.h>

#include <memory>
#include <string>

namespace pensight::msg {

template <class T>
struct RosAllocator : std::allocator<T> {
  using value_type = T;
  RosAllocator() = default;
  template <class U>
  RosAllocator(const RosAllocator<U>&) noexcept {}
  template <class U>
  struct rebind {
    using other = RosAllocator<U>;
  };
};

using CameraInfo = sensor_msgs::CameraInfo_<RosAllocator<void>>;
using CompressedImage = sensor_msgs::CompressedImage_<RosAllocator<void>>;
using FluidPressure = sensor_msgs::FluidPressure_<RosAllocator<void>>;
using Image = sensor_msgs::Image_<RosAllocator<void>>;
using Imu = sensor_msgs::Imu_<RosAllocator<void>>;
using TwistWithCovarianceStamped = geometry_msgs::TwistWithCovarianceStamped_<RosAllocator<void>>;
using Float64MultiArray = std_msgs::Float64MultiArray_<RosAllocator<void>>;

// The ROS type name of a message type ("sensor_msgs/Image").
template <class Message>
std::string type_name() {
  return ros::message_traits::DataType<Message>::value();
}

// A message string (whose allocator is RosAllocator) as a std::string.
template <class String>
std::string to_std_string(const String& s) {
  return std::string(s.data(), s.size());
}

}  // namespace pensight::msg
