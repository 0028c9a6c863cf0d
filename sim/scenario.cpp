#include "sim/scenario.h"

#include <Eigen/Geometry>
#include <cmath>
#include <fstream>
#include <numbers>
#include <optional>
#include <sstream>

#include "control/control_config.h"
#include "core/error.h"
#include "core/strict_yaml.h"
#include "core/units.h"
#include "pipeline/dataset/sensor_mounts.h"

namespace pensight::sim {
namespace {

// Reads `key` (default `fallback`) and checks lo <= value <= hi.
double ranged(const YamlMap& y, const std::string& key, double fallback, double lo, double hi) {
  const double v = y.number(key, fallback);
  if (!(v >= lo && v <= hi)) {
    y.fail(key, "must be between " + std::to_string(lo) + " and " + std::to_string(hi) + ", got " +
                    std::to_string(v));
  }
  return v;
}

double positive(const YamlMap& y, const std::string& key, double fallback) {
  const double v = y.number(key, fallback);
  if (!(v > 0)) y.fail(key, "must be positive, got " + std::to_string(v));
  return v;
}

Eigen::Vector3d vec3(const YamlMap& y, const std::string& key, const Eigen::Vector3d& fallback) {
  if (!y.has(key)) {
    y.optional_number(key);  // marks the key as known
    return fallback;
  }
  const auto v = y.numbers(key, 3);
  return {v[0], v[1], v[2]};
}

CameraConfig parse_camera(const YamlMap& y) {
  CameraConfig c;
  PinholeCamera& k = c.calibration.camera;
  c.calibration.rate_hz = ranged(y, "rate_hz", 10, 0.1, 1000);
  if (y.has("resolution")) {
    const auto r = y.numbers("resolution", 2);
    if (r[0] < 8 || r[1] < 8 || r[0] > 8192 || r[1] > 8192 || r[0] != std::round(r[0]) ||
        r[1] != std::round(r[1])) {
      y.fail("resolution", "expected [width, height], whole pixels between 8 and 8192");
    }
    k.width_px = static_cast<int>(r[0]);
    k.height_px = static_cast<int>(r[1]);
  } else {
    y.optional_number("resolution");
  }
  if (y.has("intrinsics")) {
    const auto i = y.numbers("intrinsics", 4);
    if (!(i[0] > 0 && i[1] > 0)) y.fail("intrinsics", "focal lengths must be positive");
    k.fx_px = i[0];
    k.fy_px = i[1];
    k.cx_px = i[2];
    k.cy_px = i[3];
  } else {
    y.optional_number("intrinsics");
    // Defaults scale with the resolution: 720x540 -> fx = 462, principal point at the centre.
    k.fx_px = k.fy_px = 462.0 * k.width_px / 720.0;
    k.cx_px = (k.width_px - 1) / 2.0;
    k.cy_px = (k.height_px - 1) / 2.0;
  }
  if (y.has("distortion")) {
    const auto d = y.numbers("distortion", 4);
    k.k1 = d[0];
    k.k2 = d[1];
    k.p1 = d[2];
    k.p2 = d[3];
  } else {
    y.optional_number("distortion");
  }
  c.position_B_m = vec3(y, "position_m", c.position_B_m);
  c.pan_rad = ranged(y, "pan_rad", 0, -std::numbers::pi, std::numbers::pi);
  c.tilt_rad = ranged(y, "tilt_rad", 0, -1.5, 1.5);
  c.samples_per_axis = y.integer("samples_per_axis", 3);
  if (c.samples_per_axis < 1 || c.samples_per_axis > 8) {
    y.fail("samples_per_axis", "must be 1 to 8");
  }
  c.exposure = positive(y, "exposure", c.exposure);
  c.vignetting = ranged(y, "vignetting", c.vignetting, 0, 1);
  c.read_noise = ranged(y, "read_noise", c.read_noise, 0, 100);
  c.shot_noise = ranged(y, "shot_noise", c.shot_noise, 0, 10);
  c.f_number = ranged(y, "f_number", c.f_number, 0.5, 64);
  c.pixel_pitch_m = ranged(y, "pixel_pitch_m", c.pixel_pitch_m, 0.5e-6, 50e-6);
  c.focus_distance_m = ranged(y, "focus_distance_m", c.focus_distance_m, 0, 1000);
  // The thin-lens blur circle needs the focus beyond the focal length (and a real lens focuses
  // no closer than a few focal lengths).
  const double focal_m = k.fx_px * c.pixel_pitch_m;
  if (c.focus_distance_m > 0 && !(c.focus_distance_m > 2 * focal_m)) {
    y.fail("focus_distance_m",
           "must be 0 (pinhole) or more than twice the focal length fx * "
           "pixel_pitch_m = " +
               std::to_string(focal_m) + " m");
  }
  c.exposure_time_s = ranged(y, "exposure_time_s", c.exposure_time_s, 0, 1);
  if (!(c.exposure_time_s * c.calibration.rate_hz <= 1)) {
    y.fail("exposure_time_s", "must not be longer than the frame interval 1 / rate_hz");
  }
  c.colour = y.boolean("colour", c.colour);
  c.jpeg_quality = y.integer("jpeg_quality", c.jpeg_quality);
  if (c.jpeg_quality < 0 || c.jpeg_quality > 100) {
    y.fail("jpeg_quality", "must be 0 (off) or 1 to 100");
  }
  y.check_unknown_keys();
  return c;
}

PenConfig parse_pen(const YamlMap& y) {
  PenConfig p;
  const std::string shape = y.string("shape", "cylinder");
  if (shape == "cylinder") {
    p.shape = NetShape::kCylinder;
  } else if (shape == "plane") {
    p.shape = NetShape::kPlane;
  } else {
    y.fail("shape", "must be 'cylinder' or 'plane', got '" + shape + "'");
  }
  p.radius_m = positive(y, "radius_m", p.radius_m);
  p.depth_m = positive(y, "depth_m", p.depth_m);
  p.bottom = y.boolean("bottom", p.bottom);
  p.width_m = positive(y, "width_m", p.width_m);
  p.top_m = ranged(y, "top_m", p.top_m, 0, 1000);
  p.height_m = positive(y, "height_m", p.height_m);
  p.wall_gap_m = ranged(y, "wall_gap_m", p.wall_gap_m, 0, 1000);
  p.wall_albedo = ranged(y, "wall_albedo", p.wall_albedo, 0, 1);
  y.check_unknown_keys();
  return p;
}

NetConfig parse_net(const YamlMap& y) {
  NetConfig n;
  n.bar_length_m = positive(y, "mesh_m", n.bar_length_m);
  const std::string type = y.string("mesh_type", to_string(n.mesh_type));
  const std::optional<MeshType> mesh_type = parse_mesh_type(type);
  if (!mesh_type) y.fail("mesh_type", "must be 'square' or 'diamond', got '" + type + "'");
  n.mesh_type = *mesh_type;
  n.opening_angle_deg = ranged(y, "opening_angle_deg", n.opening_angle_deg, 45, 135);
  n.opening_angle_variation_deg =
      ranged(y, "opening_angle_variation_deg", n.opening_angle_variation_deg, 0, 10);
  n.stretch_variation = ranged(y, "stretch_variation", n.stretch_variation, 0, 0.05);
  n.deform_scale_m = ranged(y, "deform_scale_m", n.deform_scale_m, 0.2, 100);
  n.twine_width_m = positive(y, "twine_width_m", n.twine_width_m);
  n.knot_size_m = ranged(y, "knot_size_m", n.knot_size_m, 0, 1);
  // Up to 30 % of the bar (heavy twine on a small mesh); the holes stay open at 45 degrees.
  if (n.twine_width_m >= 0.35 * n.bar_length_m) {
    y.fail("twine_width_m", "must be less than 0.35 * mesh_m");
  }
  if (n.knot_size_m >= 0.6 * n.bar_length_m)
    y.fail("knot_size_m", "must be less than 0.6 * mesh_m");
  const std::string knot = y.string("knot_shape", "square");
  if (knot == "square") {
    n.knot_shape = KnotShape::kSquare;
  } else if (knot == "round") {
    n.knot_shape = KnotShape::kRound;
  } else {
    y.fail("knot_shape", "must be 'square' or 'round', got '" + knot + "'");
  }
  n.albedo = ranged(y, "albedo", n.albedo, 0, 1);
  n.fouling = ranged(y, "fouling", n.fouling, 0, 1);
  n.fouling_scale_m = positive(y, "fouling_scale_m", n.fouling_scale_m);
  n.fouling_coverage = ranged(y, "fouling_coverage", n.fouling_coverage, 0, 0.7);
  if (const auto r = y.optional_map("ropes")) {
    n.ropes.spacing_m = ranged(*r, "spacing_m", n.ropes.spacing_m, 0, 1000);
    n.ropes.width_m = ranged(*r, "width_m", n.ropes.width_m, 0.001, 0.2);
    n.ropes.albedo = ranged(*r, "albedo", n.ropes.albedo, 0, 1);
    if (n.ropes.spacing_m > 0 && n.ropes.spacing_m < 4 * n.ropes.width_m) {
      r->fail("spacing_m", "must be 0 (no ropes) or at least 4 * width_m");
    }
    r->check_unknown_keys();
  }
  n.seam_spacing_m = ranged(y, "seam_spacing_m", n.seam_spacing_m, 0, 1000);
  if (n.seam_spacing_m > 0 && n.seam_spacing_m < 2 * n.bar_length_m) {
    y.fail("seam_spacing_m", "must be 0 (no seams) or at least 2 * mesh_m");
  }
  if (const auto list = y.optional_map_list("bulges")) {
    if (list->size() > kMaxBulges) y.fail("bulges", "at most 8 bulges");
    for (const YamlMap& b : *list) {
      Bulge g;
      g.along_m = b.number("along_m");
      g.depth_m = b.number("depth_m");
      g.amplitude_m = ranged(b, "amplitude_m", 0, -5, 5);
      g.radius_m = positive(b, "radius_m", 1.0);
      b.check_unknown_keys();
      n.bulges.push_back(g);
    }
  }
  y.check_unknown_keys();
  return n;
}

WaterConfig parse_water(const YamlMap& y) {
  WaterConfig w;
  w.attenuation_per_m = ranged(y, "attenuation_per_m", w.attenuation_per_m, 0.01, 20);
  w.diffuse_attenuation_per_m =
      ranged(y, "diffuse_attenuation_per_m", w.diffuse_attenuation_per_m, 0, 20);
  w.backscatter = ranged(y, "backscatter", w.backscatter, 0, 10);
  w.lamp_backscatter = ranged(y, "lamp_backscatter", w.lamp_backscatter, 0, 10);
  w.marine_snow = ranged(y, "marine_snow", w.marine_snow, 0, 1);
  w.snow_brightness = ranged(y, "snow_brightness", w.snow_brightness, 0, 10);
  w.current_mps = vec3(y, "current_mps", w.current_mps);
  if (!(w.current_mps.norm() <= 3)) y.fail("current_mps", "a water current of at most 3 m/s");
  y.check_unknown_keys();
  return w;
}

std::vector<Lamp> default_lamps() {
  Lamp left, right;
  left.position_B_m = {0.3, -0.25, 0.0};
  right.position_B_m = {0.3, 0.25, 0.0};
  return {left, right};
}

LightConfig parse_light(const YamlMap& y) {
  LightConfig l;
  l.ambient = ranged(y, "ambient", l.ambient, 0, 100);
  l.surface_brightness = ranged(y, "surface_brightness", l.surface_brightness, 0, 100);
  l.lamp_level = ranged(y, "lamp_level", l.lamp_level, 0, 1);
  if (const auto list = y.optional_map_list("lamps")) {
    if (list->size() > kMaxLamps) y.fail("lamps", "at most 4 lamps");
    for (const YamlMap& m : *list) {
      Lamp lamp;
      lamp.position_B_m = vec3(m, "position_m", lamp.position_B_m);
      lamp.direction_B = vec3(m, "direction", lamp.direction_B);
      if (!(lamp.direction_B.norm() > 1e-6)) m.fail("direction", "must not be zero");
      lamp.direction_B.normalize();
      lamp.intensity = ranged(m, "intensity", lamp.intensity, 0, 1000);
      lamp.half_angle_rad = ranged(m, "half_angle_rad", lamp.half_angle_rad, 0.01, 1.5);
      m.check_unknown_keys();
      l.lamps.push_back(lamp);
    }
  } else {
    l.lamps = default_lamps();
  }
  y.check_unknown_keys();
  return l;
}

std::vector<Fish> parse_fish(const YamlMap& y) {
  std::vector<Fish> out;
  const auto list = y.optional_map_list("fish");
  if (!list) return out;
  if (list->size() > kMaxFish) y.fail("fish", "at most 8 fish");
  for (const YamlMap& m : *list) {
    Fish f;
    f.net_distance_m = positive(m, "net_distance_m", f.net_distance_m);
    f.depth_m = positive(m, "depth_m", f.depth_m);
    f.speed_mps = ranged(m, "speed_mps", f.speed_mps, -10, 10);
    f.along_m = m.number("along_m", f.along_m);
    f.length_m = positive(m, "length_m", f.length_m);
    f.thickness_m = positive(m, "thickness_m", f.thickness_m);
    f.albedo = ranged(m, "albedo", f.albedo, 0, 1);
    m.check_unknown_keys();
    out.push_back(f);
  }
  return out;
}

DvlConfig parse_dvl(const YamlMap& y) {
  DvlConfig d;
  d.enabled = y.boolean("enabled", true);
  d.rate_hz = ranged(y, "rate_hz", d.rate_hz, 0.1, 100);
  d.position_B_m = vec3(y, "position_m", d.position_B_m);
  d.pan_rad = ranged(y, "pan_rad", 0, -std::numbers::pi, std::numbers::pi);
  d.tilt_rad = ranged(y, "tilt_rad", 0, -std::numbers::pi, std::numbers::pi);
  d.beam_angle_rad = ranged(y, "beam_angle_rad", d.beam_angle_rad, 0, 1.2);
  d.velocity_noise_mps = ranged(y, "velocity_noise_mps", d.velocity_noise_mps, 0, 10);
  d.range_noise_m = ranged(y, "range_noise_m", d.range_noise_m, 0, 10);
  d.max_range_m = positive(y, "max_range_m", d.max_range_m);
  d.dropout_probability = ranged(y, "dropout_probability", d.dropout_probability, 0, 1);
  d.spike_probability = ranged(y, "spike_probability", d.spike_probability, 0, 1);
  d.spike_mps = ranged(y, "spike_mps", d.spike_mps, 0, 100);
  d.scale_error = ranged(y, "scale_error", d.scale_error, -0.5, 0.5);
  d.bias_B_mps = vec3(y, "bias_mps", d.bias_B_mps);
  if (const auto list = y.optional_map_list("spikes")) {
    for (const YamlMap& m : *list) {
      DvlSpike spike;
      spike.t_s = ranged(m, "t_s", 0, 0, 1e6);
      spike.duration_s = positive(m, "duration_s", spike.duration_s);
      spike.velocity_B_mps = vec3(m, "velocity_mps", spike.velocity_B_mps);
      m.check_unknown_keys();
      d.spikes.push_back(spike);
    }
  }
  y.check_unknown_keys();
  return d;
}

PressureConfig parse_pressure(const YamlMap& y) {
  PressureConfig p;
  p.enabled = y.boolean("enabled", true);
  p.rate_hz = ranged(y, "rate_hz", p.rate_hz, 0.1, 1000);
  p.noise_m = ranged(y, "noise_m", p.noise_m, 0, 10);
  p.bias_m = ranged(y, "bias_m", p.bias_m, -10, 10);
  y.check_unknown_keys();
  return p;
}

AttitudeConfig parse_attitude(const YamlMap& y) {
  AttitudeConfig a;
  a.enabled = y.boolean("enabled", true);
  a.rate_hz = ranged(y, "rate_hz", a.rate_hz, 0.1, 1000);
  a.noise_rad = ranged(y, "noise_rad", a.noise_rad, 0, 1);
  y.check_unknown_keys();
  return a;
}

Waypoint parse_waypoint(const YamlMap& m) {
  Waypoint w;
  w.t_s = m.number("t_s");
  w.along_m = m.number("along_m", 0);
  w.net_distance_m = m.number("net_distance_m");
  w.depth_m = m.number("depth_m");
  w.heading_rad = m.number("heading_rad", 0);
  w.pitch_rad = ranged(m, "pitch_rad", 0, -1.5, 1.5);
  w.roll_rad = ranged(m, "roll_rad", 0, -1.5, 1.5);
  m.check_unknown_keys();
  return w;
}

// Passes along the net at each distance: horizontal rows stepping down by row_spacing_m,
// alternating direction, with straight moves between rows and distances.
std::vector<Waypoint> lawnmower(const YamlMap& y) {
  const std::vector<double> distances = y.numbers("net_distances_m");
  if (distances.empty()) y.fail("net_distances_m", "needs at least one distance");
  const double top = y.number("depth_from_m"), bottom = y.number("depth_to_m");
  const double spacing = positive(y, "row_spacing_m", 0.5);
  const double length = positive(y, "row_length_m", 3.0);
  const double speed = positive(y, "speed_mps", 0.3);
  const double along0 = y.number("along_m", 0);
  if (!(bottom >= top)) y.fail("depth_to_m", "must not be above depth_from_m");
  if (!((bottom - top) / spacing <= 1000)) y.fail("row_spacing_m", "more than 1000 rows");
  y.check_unknown_keys();
  const int rows = static_cast<int>(std::floor((bottom - top) / spacing + 1e-9)) + 1;
  std::vector<Waypoint> out;
  double t = 0;
  auto go = [&](double along, double dist, double depth) {
    if (!out.empty()) {
      const Waypoint& p = out.back();
      t += std::hypot(along - p.along_m, dist - p.net_distance_m, depth - p.depth_m) / speed;
    }
    Waypoint w;
    w.t_s = t;
    w.along_m = along;
    w.net_distance_m = dist;
    w.depth_m = depth;
    out.push_back(w);
  };
  bool forward = true;
  for (const double dist : distances) {
    for (int r = 0; r < rows; ++r) {
      const double depth = top + r * spacing;
      go(forward ? along0 : along0 + length, dist, depth);
      go(forward ? along0 + length : along0, dist, depth);
      forward = !forward;
    }
  }
  return out;
}

std::vector<Waypoint> parse_trajectory(const YamlMap& y) {
  std::vector<Waypoint> out;
  const bool has_wp = y.has("waypoints"), has_lm = y.has("lawnmower");
  if (has_wp == has_lm) {
    y.fail("waypoints", "give exactly one of 'waypoints' and 'lawnmower' under trajectory");
  }
  if (has_wp) {
    for (const YamlMap& m : y.map_list("waypoints")) out.push_back(parse_waypoint(m));
    y.optional_number("lawnmower");
  } else {
    out = lawnmower(y.map("lawnmower"));
    y.optional_number("waypoints");
  }
  for (size_t i = 1; i < out.size(); ++i) {
    if (!(out[i].t_s > out[i - 1].t_s)) {
      y.fail("waypoints[" + std::to_string(i) + "].t_s", "waypoint times must increase");
    }
  }
  y.check_unknown_keys();
  return out;
}

}  // namespace

int Scenario::num_frames() const {
  return static_cast<int>(std::floor(duration_s * camera.calibration.rate_hz + 1e-9)) + 1;
}

int64_t Scenario::frame_time_ns(int frame) const {
  return start_time_ns +
         static_cast<int64_t>(std::llround(frame * 1e9 / camera.calibration.rate_hz));
}

SceneConfig Scenario::scene_config() const {
  SceneConfig scene{net.bar_length_m, pen.radius_m, std::nullopt, net.mesh_type,
                    deg_to_rad(net.opening_angle_deg)};
  // The plane pen's net is the plane x = radius_m, facing -x (PenConfig).
  if (pen.shape == NetShape::kPlane)
    scene.flat_panel =
        SceneConfig::FlatPanel{Eigen::Vector3d(pen.radius_m, 0, 0), Eigen::Vector3d::UnitX()};
  return scene;
}

namespace {

// The closed loop's vehicle: what a scenario may change of the BlueROV2 Heavy's defaults.
void parse_vehicle(const YamlMap& y, vehicle::VehicleParams& v) {
  v.current.variation_mps = y.number("current_variation_mps", v.current.variation_mps);
  v.current.time_constant_s = y.number("current_time_constant_s", v.current.time_constant_s);
  v.autopilot.pilot_gain = y.number("pilot_gain", v.autopilot.pilot_gain);
  v.hull.water_density_kgpm3 = y.number("water_density_kgpm3", v.hull.water_density_kgpm3);
  y.check_unknown_keys();
  try {
    vehicle::check_params(v);
  } catch (const Error& e) {
    throw Error(y.file() + ": section 'vehicle': " + e.what());
  }
}

}  // namespace

Scenario parse_scenario(const std::string& text, const std::string& file_name) {
  const YamlMap y = YamlMap::parse(text, file_name);
  Scenario s;
  s.file = file_name;
  s.name = std::filesystem::path(file_name).stem().string();
  const double seed = y.number("seed", 1);
  if (seed < 0 || seed != std::floor(seed) || seed > 9e15) {
    y.fail("seed", "must be a non-negative integer");
  }
  s.seed = static_cast<uint64_t>(seed);
  s.start_time_ns = y.integer64("start_time_ns", s.start_time_ns);
  if (const auto m = y.optional_map("camera")) s.camera = parse_camera(*m);
  s.camera.calibration.T_body_camera =
      forward_mount(s.camera.position_B_m, s.camera.pan_rad, s.camera.tilt_rad);
  if (const auto m = y.optional_map("pen")) s.pen = parse_pen(*m);
  if (const auto m = y.optional_map("net")) s.net = parse_net(*m);
  if (const auto m = y.optional_map("water")) s.water = parse_water(*m);
  if (const auto m = y.optional_map("light")) {
    s.light = parse_light(*m);
  } else {
    s.light.lamps = default_lamps();
  }
  s.fish = parse_fish(y);
  if (const auto m = y.optional_map("dvl")) s.dvl = parse_dvl(*m);
  if (const auto m = y.optional_map("pressure")) s.pressure = parse_pressure(*m);
  if (const auto m = y.optional_map("attitude")) s.attitude = parse_attitude(*m);
  if (const auto m = y.optional_map("control")) s.control = control::parse_control_config(*m);
  if (const auto m = y.optional_map("vehicle")) parse_vehicle(*m, s.vehicle);
  s.vehicle.current.mean_pen_mps = s.water.current_mps;
  s.vehicle.current.seed = s.seed;
  s.waypoints = parse_trajectory(y.map("trajectory"));
  if (s.waypoints.empty()) y.fail("trajectory", "needs at least one waypoint");
  const double last = s.waypoints.back().t_s;
  s.duration_s = y.number("duration_s", last - s.waypoints.front().t_s);
  // Six hours: 216 000 frames at 10 Hz, and a bound on what the trajectory checks walk through.
  if (!(s.duration_s >= 0 && s.duration_s <= 21600)) {
    y.fail("duration_s", "must be between 0 and 21600 s (6 h; from the waypoints when absent)");
  }
  y.check_unknown_keys();
  validate(s);
  return s;
}

Scenario load_scenario(const std::filesystem::path& file) {
  if (!std::filesystem::is_regular_file(file)) {
    throw Error("scenario '" + file.string() + "' not found (see scenarios/ for examples)");
  }
  std::ifstream in(file);
  if (!in) throw Error("cannot read scenario '" + file.string() + "'");
  std::stringstream text;
  text << in.rdbuf();
  return parse_scenario(text.str(), file.string());
}

}  // namespace pensight::sim
