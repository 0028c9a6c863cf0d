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

#include <algorithm>
#include <memory>
#include <string>

namespace pensight::msg {

// The most bytes one array or string of a message may hold. ROS's deserializer sizes a vector
// from its length field before it reads the elements (and finds the stream short), so a damaged
// field would allocate gigabytes. While MessageBytesLimit is alive (the bag reader, per message)
// the bound is the serialized message's size; otherwise (the node's subscriptions, which roscpp
// deserializes) it is kMaxMessageArrayBytes: no message this project reads or writes comes near
// it (a 4K colour image is 25 MB).
inline constexpr size_t kMaxMessageArrayBytes = size_t{256} << 20;
inline thread_local size_t message_bytes_limit = kMaxMessageArrayBytes;

class MessageBytesLimit {
 public:
  explicit MessageBytesLimit(size_t bytes) : previous_(message_bytes_limit) {
    message_bytes_limit = std::min(bytes, previous_);
  }
  ~MessageBytesLimit() { message_bytes_limit = previous_; }
  MessageBytesLimit(const MessageBytesLimit&) = delete;
  MessageBytesLimit& operator=(const MessageBytesLimit&) = delete;

 private:
  size_t previous_;
};

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
  // Throws ros::serialization::StreamOverrunException (a ros::Exception, as for a short stream)
  // beyond message_bytes_limit.
  T* allocate(size_t n) {
    if (n > message_bytes_limit / sizeof(T)) {
      throw ros::serialization::StreamOverrunException(
          "an array of " + std::to_string(n) + " elements of " + std::to_string(sizeof(T)) +
          " bytes where at most " + std::to_string(message_bytes_limit) + " bytes can be");
    }
    return std::allocator<T>::allocate(n);
  }
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
