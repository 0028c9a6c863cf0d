#include "apps/ros/node_config.h"

#include <xmlrpcpp/XmlRpcValue.h>

#include <cmath>
#include <limits>
#include <set>
#include <span>
#include <vector>

#include "core/error.h"
#include "core/params.h"
#include "pipeline/dataset/calibration_yaml.h"
#include "ros/message_conversions_detail.h"

namespace pensight::node {
namespace {

constexpr ParamRange at_least(double min) {
  return {min, std::numeric_limits<double>::infinity()};
}

// The numbers and flags, one table per part of NodeConfig they fill (keys without the "~"); the
// strings and enums are read one by one in read_node_config.
//
// Read only without ~scene, whose scene.yaml says both.
const Param<SceneConfig> kSceneParams[] = {
    {"mesh_size_m", &SceneConfig::bar_length_m, "m", kPositive,
     "net bar length, knot to knot (without ~scene)"},
    {"pen_radius_m", &SceneConfig::pen_radius_m, "m", kPositive,
     "pen radius (without ~scene); a flat net is a large radius (e.g. 100)"},
};

const Param<NodeConfig> kNodeParams[] = {
    {"has_dvl", &NodeConfig::has_dvl, "", {}, "the vehicle has a DVL"},
    {"has_pressure", &NodeConfig::has_pressure, "", {}, "the vehicle has a pressure sensor"},
    {"has_imu", &NodeConfig::has_imu, "", {}, "the vehicle has an IMU"},
    {"map_rate_hz", &NodeConfig::map_rate_hz, "Hz", kNonNegative,
     "~map publications per second (0: no map)"},
    {"camera_info_timeout_s", &NodeConfig::camera_info_timeout_s, "s", kPositive,
     "error log period while no camera_info arrives"},
    {"sensor_wait_s", &NodeConfig::sensor_wait_s, "s", closed_range(0, 1),
     "how long a frame's global pose waits for a sensor sample due by the frame's time"},
};

const Param<kernels::RoiGrid> kGridParams[] = {
    {"roi_rows", &kernels::RoiGrid::rows, "", at_least(1), "rows of the FFT's ROI grid"},
    {"roi_cols", &kernels::RoiGrid::cols, "", at_least(1), "columns of the FFT's ROI grid"},
    {"roi_size_px", &kernels::RoiGrid::roi_size_px, "px", at_least(0),
     "ROI side in image pixels, at least 16; 0: from fx and the bar length"},
};

const Param<NetDetectorConfig> kDetectorParams[] = {
    {"cpu_threads", &NetDetectorConfig::cpu_threads, "", kNonNegative,
     "net detection's CPU threads (0: all hardware threads)"},
};

const Param<WaterColumn> kWaterParams[] = {
    {"water_density", &WaterColumn::density_kg_m3, "kg/m^3", kPositive,
     "pressure to depth; sea water 1025, fresh water ~1000"},
    {"surface_pressure_pa", &WaterColumn::surface_pressure_pa, "Pa", kNonNegative,
     "the atmosphere at the surface: 101325"},
};

const std::vector<std::string> kTextParameters = {
    "scene",         "camera_yaml",         "dvl_yaml",  "backend",    "model",
    "depth_backend", "depth_cpu_inference", "pen_frame", "base_frame", "camera_frame"};

template <class Config>
void add_keys(std::span<const Param<Config>> params, std::vector<std::string>& names) {
  for (const Param<Config>& p : params) names.emplace_back(p.key);
}

// Every private parameter the node takes.
const std::vector<std::string>& known_parameters() {
  static const std::vector<std::string> names = [] {
    std::vector<std::string> all = kTextParameters;
    add_keys<SceneConfig>(kSceneParams, all);
    add_keys<NodeConfig>(kNodeParams, all);
    add_keys<kernels::RoiGrid>(kGridParams, all);
    add_keys<NetDetectorConfig>(kDetectorParams, all);
    add_keys<WaterColumn>(kWaterParams, all);
    return all;
  }();
  return names;
}

std::string known_list() {
  std::string out;
  for (const std::string& p : known_parameters()) out.append(out.empty() ? "~" : ", ~").append(p);
  return out;
}

// The node's private parameters as given, one value each.
class Params {
 public:
  explicit Params(const ros::NodeHandle& nh) : nh_(nh) {
    const std::string prefix = nh.getNamespace() + "/";
    std::vector<std::string> names;
    ros::NodeHandle(nh).getParamNames(names);
    const std::set<std::string> known(known_parameters().begin(), known_parameters().end());
    for (const std::string& full : names) {
      if (!full.starts_with(prefix)) continue;
      const std::string name = full.substr(prefix.size());
      if (!known.count(name.substr(0, name.find('/')))) {
        throw Error("~" + name + ": unknown parameter of " + nh.getNamespace() +
                    " (a typo?); it takes " + known_list());
      }
    }
  }

  std::optional<std::string> text(const std::string& name) const {
    XmlRpc::XmlRpcValue v;
    if (!nh_.getParam(name, v)) return std::nullopt;
    if (v.getType() != XmlRpc::XmlRpcValue::TypeString) fail(name, "a string");
    return static_cast<std::string>(v);
  }
  std::optional<double> number(const std::string& name) const {
    XmlRpc::XmlRpcValue v;
    if (!nh_.getParam(name, v)) return std::nullopt;
    if (v.getType() == XmlRpc::XmlRpcValue::TypeInt) return static_cast<int>(v);
    if (v.getType() != XmlRpc::XmlRpcValue::TypeDouble) fail(name, "a number");
    const double d = static_cast<double>(v);
    if (!std::isfinite(d)) fail(name, "a finite number");
    return d;
  }
  std::optional<int> integer(const std::string& name) const {
    XmlRpc::XmlRpcValue v;
    if (!nh_.getParam(name, v)) return std::nullopt;
    if (v.getType() != XmlRpc::XmlRpcValue::TypeInt) fail(name, "an integer");
    return static_cast<int>(v);
  }
  std::optional<bool> flag(const std::string& name) const {
    XmlRpc::XmlRpcValue v;
    if (!nh_.getParam(name, v)) return std::nullopt;
    if (v.getType() != XmlRpc::XmlRpcValue::TypeBoolean) fail(name, "true or false");
    return static_cast<bool>(v);
  }

  [[noreturn]] static void fail(const std::string& name, const std::string& takes) {
    error(name, "takes " + takes);
  }
  [[noreturn]] static void error(const std::string& name, const std::string& message) {
    throw Error("~" + name + ": " + message);
  }

 private:
  const ros::NodeHandle& nh_;
};

// Reads the parameters of `params` that the server has into `config`, each as its member's type,
// checking its range: "~KEY: VALUE is outside RANGE UNIT (HELP)".
template <class Config>
void read_ros_params(const Params& server, std::span<const Param<Config>> params, Config& config) {
  for (const Param<Config>& p : params) {
    const std::string key(p.key);
    if (const auto* flag = std::get_if<bool Config::*>(&p.member)) {
      if (const auto v = server.flag(key)) config.*(*flag) = *v;
      continue;
    }
    const auto* integer = std::get_if<int Config::*>(&p.member);
    std::optional<double> v;
    if (integer) {
      v = server.integer(key);
    } else {
      v = server.number(key);
    }
    if (!v) continue;
    if (!p.range.contains(*v)) Params::error(key, param_range_error(*v, p.range, p.unit, p.help));
    if (integer) {
      config.*(*integer) = static_cast<int>(*v);
    } else if (const auto* number = std::get_if<double Config::*>(&p.member)) {
      config.*(*number) = *v * p.scale;
    } else {
      config.*std::get<std::optional<double> Config::*>(p.member) = *v * p.scale;
    }
  }
}

std::string frame_name(const Params& p, const std::string& name, const std::string& fallback) {
  const std::string v = p.text(name).value_or(fallback);
  if (v.empty() || v.front() == '/') Params::fail(name, "a tf frame name without a leading '/'");
  return v;
}

}  // namespace

std::string node_params_markdown() {
  const NodeConfig d;
  std::string rows(kParamTableHeader);
  rows += param_table_rows<SceneConfig>(kSceneParams, d.scene, "~");
  rows += param_table_rows<NodeConfig>(kNodeParams, d, "~");
  rows += param_table_rows<kernels::RoiGrid>(kGridParams, d.detector.grid, "~");
  rows += param_table_rows<NetDetectorConfig>(kDetectorParams, d.detector, "~");
  rows += param_table_rows<WaterColumn>(kWaterParams, d.water, "~");
  return rows;
}

NodeConfig read_node_config(const ros::NodeHandle& private_nh) {
  const Params p(private_nh);
  NodeConfig c;
  if (const auto scene = p.text("scene")) {
    if (p.number("mesh_size_m") || p.number("pen_radius_m")) {
      throw Error(
          "~scene and ~mesh_size_m / ~pen_radius_m both given: the scene.yaml says both; "
          "give one or the other");
    }
    c.scene = read_scene_yaml(*scene);
  } else {
    read_ros_params<SceneConfig>(p, kSceneParams, c.scene);
  }
  if (const auto file = p.text("camera_yaml")) c.camera = read_camera_yaml(*file);
  const auto dvl_file = p.text("dvl_yaml");
  c.dvl = dvl_file ? read_dvl_yaml(*dvl_file) : default_dvl_calibration(c.dvl.rate_hz);
  read_ros_params<NodeConfig>(p, kNodeParams, c);
  read_ros_params<kernels::RoiGrid>(p, kGridParams, c.detector.grid);
  read_ros_params<NetDetectorConfig>(p, kDetectorParams, c.detector);
  read_ros_params<WaterColumn>(p, kWaterParams, c.water);
  try {
    c.detector.backend = parse_backend(p.text("backend").value_or("auto"));
    c.depth_backend = parse_backend(p.text("depth_backend").value_or("auto"));
    c.depth_cpu_inference = parse_cpu_inference(p.text("depth_cpu_inference").value_or("auto"));
  } catch (const Error& e) {
    throw Error(std::string("~backend / ~depth_backend / ~depth_cpu_inference: ") + e.what());
  }
  c.model = p.text("model").value_or(c.model);
  if (c.model.empty()) Params::fail("model", "auto, none or an ONNX file");
  c.pen_frame = frame_name(p, "pen_frame", c.pen_frame);
  c.base_frame = frame_name(p, "base_frame", c.base_frame);
  c.camera_frame = frame_name(p, "camera_frame", c.camera_frame);
  return c;
}

}  // namespace pensight::node
