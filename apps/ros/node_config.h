#pragma once
// pensight_node's parameters, read from the node's private namespace on the parameter server
// (docs/ros.md lists them with their defaults). Read strictly, like the project's YAML: an unknown
// private parameter (a typo), a value of the wrong type or out of range is an error naming
// `~name` and what it takes, so the node stops at start-up with one clear line instead of
// running on a default the user did not mean.
#include <ros/node_handle.h>

#include <optional>
#include <string>

#include "core/dataset_types.h"
#include "pipeline/depth/depth_estimator.h"
#include "pipeline/fft/net_detector.h"
#include "ros/pressure_depth.h"

namespace pensight::node {

struct NodeConfig {
  // ~scene (a scene.yaml, dataset-format.md), else ~mesh_size_m and ~pen_radius_m.
  SceneConfig scene;
  // ~camera_yaml (a cam0/sensor.yaml): intrinsics and mount; else the camera_info topic gives the
  // intrinsics and the camera sits at the body origin looking forward.
  std::optional<CameraCalibration> camera;
  // ~dvl_yaml (a dvl0/sensor.yaml); else default_dvl_calibration (message_conversions.h).
  DvlCalibration dvl;
  // ~has_dvl, ~has_pressure, ~has_imu: which sensors the vehicle has (the estimator announces
  // the absent ones and does without them).
  bool has_dvl = true, has_pressure = true, has_imu = true;
  // ~roi_rows, ~roi_cols, ~roi_size_px, ~backend (auto|cpu|vulkan|cuda), ~cpu_threads.
  NetDetectorConfig detector;
  // ~model: "auto" (the shipped compact_depth*.onnx that sees most of the frame, else no depth),
  // "none", or an ONNX file; ~depth_backend (auto|cpu|vulkan), ~depth_cpu_inference
  // (auto|opencv|engine).
  std::string model = "auto";
  Backend depth_backend = Backend::kAuto;
  CpuInference depth_cpu_inference = CpuInference::kAuto;
  WaterColumn water;  // ~water_density (kg/m^3), ~surface_pressure_pa
  // ~pen_frame, ~base_frame, ~camera_frame: the tf frame names.
  std::string pen_frame = "pen", base_frame = "base_link", camera_frame = "camera";
  double map_rate_hz = 1.0;  // ~map_rate_hz: ~map publications per second; 0 turns the map off
  double camera_info_timeout_s = 5.0;  // ~camera_info_timeout_s: error log period while waiting
  // ~sensor_wait_s: how long a frame's global pose waits for a sensor sample due by its time
  // (PipelineConfig::sensor_wait_ms); topics deliver samples just after the frame they precede.
  double sensor_wait_s = 0.05;
};

// Throws pensight::Error naming the parameter for the problems above ("~roi_rows: 0 is outside
// >= 1 (...)" for a number out of its range, as core/params.h words it), and as read_scene_yaml,
// read_camera_yaml and read_dvl_yaml for the files they name.
NodeConfig read_node_config(const ros::NodeHandle& private_nh);

// The Markdown table (core/params.h's param_table_rows under kParamTableHeader) of the numbers
// and flags, keys written `~name`, defaults those of NodeConfig{}: docs/ros.md's generated section
// (`pensight_node --params`).
std::string node_params_markdown();

}  // namespace pensight::node
