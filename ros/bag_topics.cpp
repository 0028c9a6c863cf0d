#include "ros/bag_topics.h"

#include "core/strict_yaml.h"

namespace pensight {

BagTopics read_bag_topics(const std::filesystem::path& file) {
  const YamlMap y = YamlMap::load_file(file, UnknownKeys::kReject);
  BagTopics t;
  const auto read = [&](const char* role, std::string& topic) {
    topic = y.string(role, topic);
    if (topic.empty()) y.fail(role, "a topic name such as '/camera/image_raw', not empty");
  };
  read("image", t.image);
  read("image_compressed", t.image_compressed);
  read("camera_info", t.camera_info);
  read("dvl_twist", t.dvl_twist);
  read("dvl_ranges", t.dvl_ranges);
  read("pressure", t.pressure);
  read("imu", t.imu);
  y.check_unknown_keys();
  return t;
}

}  // namespace pensight
