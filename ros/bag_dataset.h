#pragma once
// A ROS 1 bag converted to the dataset layout of ../shared/dataset-format.md (docs/ros.md), so
// that everything that reads a dataset (`pensight run`, evaluate, map) reads a bag.
//   camera image (sensor_msgs/Image or CompressedImage), header.stamp -> cam0/data/*.png (grey)
//   camera_info (sensor_msgs/CameraInfo) or --camera     -> cam0/sensor.yaml
//   dvl_twist (geometry_msgs/TwistWithCovarianceStamped) -> dvl0/data.csv vx, vy, vz, valid:
//     the body-frame (FRD) velocity over the net; a NaN component means no lock: valid 0
//   dvl_ranges (std_msgs/Float64MultiArray, 4 ranges [m]) -> dvl0/data.csv r1..r4 of the twist
//     nearest in time (bag time against header.stamp, within kDvlRangesMatchWindow_ns); a range
//     that is not finite or not > 0 is "no return" (NaN)
//   pressure (sensor_msgs/FluidPressure, Pa)             -> pressure0/data.csv depth
//   imu (sensor_msgs/Imu orientation, REP 103 ENU/FLU)   -> imu0/attitude.csv (ros_frames.h)
//   --scene scene.yaml                                   -> scene.yaml
// The camera stream is strict: a frame out of time order, a frame of the wrong size or an
// undecodable image is an error. The sensor logs follow the dataset reader's rule
// (docs/reliability.md): a message out of time order or with a NaN value is skipped, warned about
// (the first 5 per topic, then a count) and counted, and a topic fails when more than
// kMaxSkippedRowFraction of its messages are bad.
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "ros/bag_topics.h"
#include "ros/pressure_depth.h"

namespace pensight {

// A range message further than this from a twist's stamp is not that ping's.
inline constexpr int64_t kDvlRangesMatchWindow_ns = 100'000'000;

struct BagConversionOptions {
  std::filesystem::path scene_file;   // scene.yaml (required: a bag does not know the net)
  std::filesystem::path camera_file;  // cam0/sensor.yaml; empty: from the camera_info topic
  std::filesystem::path dvl_file;     // dvl0/sensor.yaml; empty: a default mount (docs/ros.md)
  BagTopics topics;
  WaterColumn water;
};

// Messages of one sensor topic that were skipped (out of time order, NaN, malformed).
struct SkippedMessages {
  std::string topic;
  size_t skipped = 0;
  size_t messages = 0;  // on the topic, skipped ones included
};

struct BagConversionSummary {
  size_t frames = 0, dvl_samples = 0, pressure_samples = 0, attitude_samples = 0;
  std::string image_topic;  // the camera topic read
  std::vector<SkippedMessages> skipped;
};

// Writes the dataset to `out` through DatasetWriter: `out` may be absent, an empty folder or an
// earlier dataset, which is replaced; nothing appears there unless the whole bag converted.
// Sensors whose topic is not in the bag are absent from the dataset (no folder). Without
// camera_file the camera sits at the body origin looking forward, without dvl_file the DVL sits
// there too (both said once as a note).
// Throws pensight::Error naming the file, topic or option and the fix for: a missing scene_file,
// a bag that is missing, unreadable, unindexed or empty, no camera topic, no calibration (neither
// camera_info nor camera_file), a topic of another type than its role's, a camera stream error
// (above), a sensor topic with too many bad messages, or unusable options.
BagConversionSummary bag_to_dataset(const std::filesystem::path& bag_file,
                                    const std::filesystem::path& out,
                                    const BagConversionOptions& options);

}  // namespace pensight
