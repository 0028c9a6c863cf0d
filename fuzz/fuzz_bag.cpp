// A ROS 1 bag (bag_to_dataset), recorded by other tools: rosbag's records and the messages in them.
#include "fuzz/fuzz_input.h"
#include "ros/bag_dataset.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  pensight::fuzz::quiet_log();
  static const std::string kScene =
      "net_mesh_size_m: 0.03\npen_radius_m: 12\nnet_mesh_type: square\nnet_mesh_angle_deg: 90\n";
  static const auto scene = pensight::fuzz::write_input(
      reinterpret_cast<const uint8_t*>(kScene.data()), kScene.size(), "scene.yaml");
  const auto bag = pensight::fuzz::write_input(data, size, "input.bag");
  pensight::BagConversionOptions options;
  options.scene_file = scene;
  pensight::fuzz::expect_clean_error(
      [&] { pensight::bag_to_dataset(bag, pensight::fuzz::work_dir() / "out", options); });
  return 0;
}
