#include "apps/bag_input.h"

#include <cstdio>

#include "core/error.h"
#include "core/log.h"

namespace pensight::app {
namespace fs = std::filesystem;

void add_bag_options(CLI::App& cli, BagInputOptions& o) {
  o.options = {
      cli.add_option("--scene", o.scene_file,
                     "scene.yaml of the pen (dataset-format.md); required for a bag, which does "
                     "not know the net"),
      cli.add_option("--camera", o.camera_file,
                     "cam0/sensor.yaml of the camera (intrinsics and mount); default: the bag's "
                     "camera_info, the camera at the body origin looking forward"),
      cli.add_option("--dvl-sensor", o.dvl_file,
                     "dvl0/sensor.yaml of the DVL; default: at the body origin looking forward, "
                     "Janus beams at 25 deg"),
      cli.add_option("--topics", o.topics_file,
                     "YAML mapping role -> topic (roles: image, image_compressed, camera_info, "
                     "dvl_twist, dvl_ranges, pressure, imu; docs/ros.md)"),
      cli.add_option("--water-density", o.water.density_kg_m3,
                     "water density for depth from pressure [kg/m^3]")
          ->capture_default_str(),
      cli.add_option("--surface-pressure", o.water.surface_pressure_pa,
                     "pressure at the surface [Pa]")
          ->capture_default_str(),
  };
}

bool any_bag_option_given(const BagInputOptions& o) {
  for (const CLI::Option* option : o.options)
    if (option->count() > 0) return true;
  return false;
}

bool is_bag_file(const fs::path& input) {
  return input.extension() == ".bag" && !fs::is_directory(input);
}

#if PENSIGHT_HAS_ROS
void convert_bag(const fs::path& bag, const fs::path& out, const BagInputOptions& o, bool quiet) {
  BagConversionOptions options;
  options.scene_file = o.scene_file;
  options.camera_file = o.camera_file;
  options.dvl_file = o.dvl_file;
  if (!o.topics_file.empty()) options.topics = read_bag_topics(o.topics_file);
  options.water = o.water;
  const BagConversionSummary s = bag_to_dataset(bag, out, options);
  if (quiet) return;
  std::string skipped;
  for (const SkippedMessages& k : s.skipped) {
    skipped += "; " + std::to_string(k.skipped) + " of " + std::to_string(k.messages) + " on " +
               k.topic + " skipped";
  }
  log_info("bag " + bag.string() + ": " + std::to_string(s.frames) + " frames (" + s.image_topic +
           "), " + std::to_string(s.dvl_samples) + " DVL, " + std::to_string(s.pressure_samples) +
           " pressure, " + std::to_string(s.attitude_samples) + " attitude samples" + skipped);
}

ConvertedBag::ConvertedBag(const fs::path& bag, const fs::path& out_dir, const BagInputOptions& o,
                           bool quiet)
    : dir_(out_dir / ".bag_dataset") {
  std::error_code ec;
  const bool created = fs::create_directories(out_dir, ec);
  if (ec) throw Error("cannot create '" + out_dir.string() + "': " + ec.message());
  try {
    convert_bag(bag, dir_, o, quiet);
  } catch (...) {
    if (created) fs::remove(out_dir, ec);  // still empty: a failed conversion leaves nothing
    throw;
  }
}
#else
namespace {

[[noreturn]] void built_without_ros(const fs::path& bag) {
  throw Error("cannot read '" + bag.string() +
              "': pensight was built without ROS; install the ROS 1 bag packages and rebuild "
              "with `scripts/setup.sh --with-ros` (docs/ros.md)");
}

}  // namespace

void convert_bag(const fs::path& bag, const fs::path&, const BagInputOptions&, bool) {
  built_without_ros(bag);
}

ConvertedBag::ConvertedBag(const fs::path& bag, const fs::path&, const BagInputOptions&, bool) {
  built_without_ros(bag);
}
#endif

ConvertedBag::~ConvertedBag() {
  std::error_code ec;
  fs::remove_all(dir_, ec);
}

}  // namespace pensight::app
