#pragma once
// ROS bags on the command line (docs/ros.md): the options that `pensight bag-to-dataset` and
// `pensight run BAG.bag` share, and the conversion behind both. In a build without the ROS layer
// the options still parse, and converting throws an error that says how to get ROS.
#include <CLI/CLI.hpp>
#include <filesystem>
#include <string>
#include <vector>

#include "ros/bag_dataset.h"

namespace pensight::app {

struct BagInputOptions {
  std::string scene_file, camera_file, dvl_file, topics_file;
  WaterColumn water;
  std::vector<CLI::Option*> options;  // the options above, to tell whether any was given
};

// Adds --scene, --camera, --dvl-sensor, --topics, --water-density and --surface-pressure.
void add_bag_options(CLI::App& cli, BagInputOptions& o);
bool any_bag_option_given(const BagInputOptions& o);

// Whether `input` names a bag: a path ending in .bag that is not a folder.
bool is_bag_file(const std::filesystem::path& input);

// bag_to_dataset with the options, then one summary line unless `quiet`. Throws pensight::Error
// as bag_to_dataset does, or when pensight was built without ROS.
void convert_bag(const std::filesystem::path& bag, const std::filesystem::path& out,
                 const BagInputOptions& o, bool quiet);

// A bag converted into OUT/.bag_dataset for `pensight run`, removed again on destruction.
class ConvertedBag {
 public:
  // Creates out_dir when needed; throws as convert_bag.
  ConvertedBag(const std::filesystem::path& bag, const std::filesystem::path& out_dir,
               const BagInputOptions& o, bool quiet);
  ~ConvertedBag();
  ConvertedBag(const ConvertedBag&) = delete;
  ConvertedBag& operator=(const ConvertedBag&) = delete;

  const std::filesystem::path& dataset_dir() const { return dir_; }

 private:
  std::filesystem::path dir_;
};

}  // namespace pensight::app
