#include "apps/ros/node_config.h"

#include <xmlrpcpp/XmlRpcValue.h>

#include <cmath>
#include <set>
#include <vector>

#include "core/error.h"
#include "pipeline/dataset/calibration_yaml.h"
#include "ros/message_conversions_detail.h"

namespace pensight::node {
namespace {

const std::vector<std::string> kParameters = {"scene",
                                              "mesh_size_m",
                                              "pen_radius_m",
                                              "camera_yaml",
                                              "dvl_yaml",
                                              "has_dvl",
                                              "has_pressure",
                                              "has_imu",
                                              "roi_rows",
                                              "roi_cols",
                                              "roi_size_px",
                                              "backend",
                                              "cpu_threads",
                                              "model",
                                              "depth_backend",
                                              "depth_cpu_inference",
                                              "water_density",
                                              "surface_pressure_pa",
                                              "pen_frame",
                                              "base_frame",
                                              "camera_frame",
                                              "map_rate_hz",
                                              "camera_info_timeout_s",
                                              "sensor_wait_s"};

std::string known_list() {
  std::string out;
  for (const std::string& p : kParameters) out += (out.empty() ? "~" : ", ~") + p;
  return out;
}

// The node's private parameters as given, one value each.
class Params {
 public:
  explicit Params(const ros::NodeHandle& nh) : nh_(nh) {
    const std::string prefix = nh.getNamespace() + "/";
    std::vector<std::string> names;
    ros::NodeHandle(nh).getParamNames(names);
    const std::set<std::string> known(kParameters.begin(), kParameters.end());
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
    throw Error("~" + name + ": takes " + takes);
  }

 private:
  const ros::NodeHandle& nh_;
};

double positive(const Params& p, const std::string& name, double fallback) {
  const double v = p.number(name).value_or(fallback);
  if (!(v > 0)) Params::fail(name, "a number > 0 (got " + std::to_string(v) + ")");
  return v;
}

int at_least(const Params& p, const std::string& name, int fallback, int min) {
  const int v = p.integer(name).value_or(fallback);
  if (v < min) Params::fail(name, "an integer >= " + std::to_string(min));
  return v;
}

std::string frame_name(const Params& p, const std::string& name, const std::string& fallback) {
  const std::string v = p.text(name).value_or(fallback);
  if (v.empty() || v.front() == '/') Params::fail(name, "a tf frame name without a leading '/'");
  return v;
}

}  // namespace

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
    c.scene.bar_length_m = positive(p, "mesh_size_m", c.scene.bar_length_m);
    c.scene.pen_radius_m = positive(p, "pen_radius_m", c.scene.pen_radius_m);
  }
  if (const auto file = p.text("camera_yaml")) c.camera = read_camera_yaml(*file);
  const auto dvl_file = p.text("dvl_yaml");
  c.dvl = dvl_file ? read_dvl_yaml(*dvl_file) : default_dvl_calibration(c.dvl.rate_hz);
  c.has_dvl = p.flag("has_dvl").value_or(c.has_dvl);
  c.has_pressure = p.flag("has_pressure").value_or(c.has_pressure);
  c.has_imu = p.flag("has_imu").value_or(c.has_imu);

  kernels::RoiGrid& grid = c.detector.grid;
  grid.rows = at_least(p, "roi_rows", grid.rows, 1);
  grid.cols = at_least(p, "roi_cols", grid.cols, 1);
  grid.size_px = at_least(p, "roi_size_px", grid.size_px, 16);
  c.detector.cpu_threads = at_least(p, "cpu_threads", c.detector.cpu_threads, 0);
  try {
    c.detector.backend = parse_backend(p.text("backend").value_or("auto"));
    c.depth_backend = parse_backend(p.text("depth_backend").value_or("auto"));
    c.depth_cpu_inference = parse_cpu_inference(p.text("depth_cpu_inference").value_or("auto"));
  } catch (const Error& e) {
    throw Error(std::string("~backend / ~depth_backend / ~depth_cpu_inference: ") + e.what());
  }
  c.model = p.text("model").value_or(c.model);
  if (c.model.empty()) Params::fail("model", "auto, none or an ONNX file");

  c.water.density_kg_m3 = positive(p, "water_density", c.water.density_kg_m3);
  c.water.surface_pressure_pa =
      p.number("surface_pressure_pa").value_or(c.water.surface_pressure_pa);
  if (!(c.water.surface_pressure_pa >= 0)) {
    Params::fail("surface_pressure_pa", "a pressure >= 0 Pa (the atmosphere: 101325)");
  }
  c.pen_frame = frame_name(p, "pen_frame", c.pen_frame);
  c.base_frame = frame_name(p, "base_frame", c.base_frame);
  c.camera_frame = frame_name(p, "camera_frame", c.camera_frame);
  c.map_rate_hz = p.number("map_rate_hz").value_or(c.map_rate_hz);
  if (!(c.map_rate_hz >= 0)) Params::fail("map_rate_hz", "a rate >= 0 Hz (0: no map)");
  c.camera_info_timeout_s = positive(p, "camera_info_timeout_s", c.camera_info_timeout_s);
  c.sensor_wait_s = p.number("sensor_wait_s").value_or(c.sensor_wait_s);
  if (!(c.sensor_wait_s >= 0 && c.sensor_wait_s <= 1)) {
    Params::fail("sensor_wait_s", "a time in [0, 1] s");
  }
  return c;
}

}  // namespace pensight::node
