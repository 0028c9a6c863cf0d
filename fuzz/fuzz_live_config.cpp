// The live session's YAML (parse_record_config) and the camera URI in it (parse_camera_uri),
// written by users and tools. The input is parsed as the YAML, with calibration files cam0.yaml,
// dvl0.yaml and scene.yaml beside it, and its first line as a URI.
#include "fuzz/fuzz_input.h"
#include "live/camera_uri.h"
#include "live/record_config.h"
#include "pipeline/dataset/calibration_yaml.h"

namespace {

void write_calibrations() {
  static const bool written = [] {
    const std::string cam = pensight::camera_yaml({}), scene = pensight::scene_yaml({});
    pensight::DvlCalibration dvl;
    for (auto& b : dvl.beam_directions_S) b = Eigen::Vector3d::UnitZ();
    const std::string dvl_text = pensight::dvl_yaml(dvl);
    pensight::fuzz::write_input(reinterpret_cast<const uint8_t*>(cam.data()), cam.size(),
                                "cam0.yaml");
    pensight::fuzz::write_input(reinterpret_cast<const uint8_t*>(dvl_text.data()), dvl_text.size(),
                                "dvl0.yaml");
    pensight::fuzz::write_input(reinterpret_cast<const uint8_t*>(scene.data()), scene.size(),
                                "scene.yaml");
    return true;
  }();
  (void)written;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  pensight::fuzz::quiet_log();
  write_calibrations();
  const std::string text(reinterpret_cast<const char*>(data), size);
  pensight::fuzz::expect_clean_error(
      [&] { pensight::live::parse_camera_uri(text.substr(0, text.find('\n'))); });
  pensight::fuzz::expect_clean_error(
      [&] { pensight::live::parse_record_config(text, "live.yaml", pensight::fuzz::work_dir()); });
  return 0;
}
