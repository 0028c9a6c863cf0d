#pragma once
// A scenario of the synthetic net-pen world: the pen and its net, water and light, the vehicle's
// sensors and its trajectory, and the random seed. Parsed strictly from YAML (docs/sim.md gives
// every key); all lengths in metres, angles in radians, frames as in dataset-format.md.
#include <Eigen/Core>
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "control/control_config.h"
#include "core/dataset_types.h"
#include "vehicle/bluerov2_params.h"

namespace pensight::sim {

enum class NetShape { kCylinder, kPlane };

// A smooth Gaussian dent of the net, pushed towards the pen's centre (amplitude > 0) as a current
// does; `along_m` is the arc length along the net, `depth_m` the depth of its centre. A fold
// instead: two panels meeting in a vertical line at along_m, amplitude_m in from the wall there
// (< 0: out), back on the wall radius_m to either side, at every depth: a tent of three folds.
struct Bulge {
  double along_m = 0, depth_m = 0, amplitude_m = 0, radius_m = 1;
  bool fold = false;
};

// A fold's slope |amplitude_m| / radius_m at most this: the bulged surface's fixed-point
// intersection (net_geometry.h) converges within its steps up to slopes of about 0.5.
inline constexpr double kMaxFoldSlope = 0.5;

struct PenConfig {
  NetShape shape = NetShape::kCylinder;
  // Cylinder: net radius. Plane: the net is the plane x = radius_m (facing -x), which is also
  // the radius written to scene.yaml so that cylinder-based estimators see a near-flat wall.
  double radius_m = kDefaultPenRadius_m;
  double depth_m = 15.0;  // cylinder: depth of the net wall's lower edge (and of the bottom)
  bool bottom = true;     // cylinder: flat bottom net at depth_m
  // Plane (test tank): net rectangle centred at along = 0.
  double width_m = 4.9, top_m = 0.5, height_m = 1.5;
  double wall_gap_m = 1.0;  // plane: basin wall this far behind the net (0: open water)
  double wall_albedo = 0.3;
};

// Ropes across the wall (horizontal and vertical, every spacing_m), drawn over the twines.
struct RopeConfig {
  double spacing_m = 0;  // 0: no ropes
  double width_m = 0.02;
  double albedo = 0.6;
};

enum class KnotShape { kSquare, kRound };

struct NetConfig {
  // The mesh (sim/net_mesh.h): knots at i b1 + j b2 in the net surface coordinates, |b1| =
  // |b2| = bar_length_m (the bar, knot to knot), angle(b1, b2) = opening_angle_deg. Square: b1
  // along the wall's horizontal; diamond: bars at +-opening/2 from the vertical.
  double bar_length_m = 0.030;
  MeshType mesh_type = MeshType::kSquare;
  double opening_angle_deg = 90;
  // Slow deformation of the lattice (currents, weights) over deform_scale_m.
  double opening_angle_variation_deg = 0;
  double stretch_variation = 0;
  double deform_scale_m = 3;
  double twine_width_m = 0.0035;  // perpendicular to the twine
  double knot_size_m = 0.006;     // knots at the crossings (0: knotless)
  KnotShape knot_shape = KnotShape::kSquare;
  double albedo = 0.7;
  double fouling = 0.0;  // 0..1: depth of the slowly varying albedo loss
  double fouling_scale_m = 0.6;
  double fouling_coverage = 0;  // 0..0.7: share of the net in fouled patches
  RopeConfig ropes;
  double seam_spacing_m = 0;  // lacing lines along the vertical (0: none)
  std::vector<Bulge> bulges;  // at most kMaxBulges
};

struct WaterConfig {
  double attenuation_per_m = 0.25;          // beam attenuation c (Beer-Lambert)
  double diffuse_attenuation_per_m = 0.12;  // Kd: ambient light falls off as exp(-Kd z)
  double backscatter = 0.2;                 // veiling light, as a share of the ambient light
  double lamp_backscatter = 0.03;           // veiling light from the lamps, per unit intensity
  // Marine snow: particles fixed in the water, which drifts with `current_mps` (in P); the
  // density is given as the expected number in view per 24x24 px of a 720x540, fx = 462 image.
  double marine_snow = 0.04;
  double snow_brightness = 0.3;
  Eigen::Vector3d current_mps{0.04, 0.02, 0.003};
};

struct Lamp {
  Eigen::Vector3d position_B_m{0.3, 0.0, 0.0};
  Eigen::Vector3d direction_B{1.0, 0.0, 0.0};  // unit after parsing
  double intensity = 0.06;                     // irradiance at 1 m on the axis, in clear water
  double half_angle_rad = 0.5;                 // half intensity at this angle off the axis
};

struct LightConfig {
  double ambient = 1.0;  // irradiance just below the surface (0: night)
  double surface_brightness = 1.5;
  double lamp_level = 1.0;  // dimmer for all lamps (0..1)
  std::vector<Lamp> lamps;  // at most kMaxLamps
};

// A fish swimming along the net at a fixed distance from it.
struct Fish {
  double net_distance_m = 0.3, depth_m = 3, speed_mps = 0.5, along_m = 0;
  double length_m = 0.45, thickness_m = 0.1, albedo = 0.45;
};

struct CameraConfig {
  CameraCalibration
      calibration;  // intrinsics, size, rate; T_body_camera built from the mount below
  Eigen::Vector3d position_B_m{0.3, 0.0, 0.0};
  double pan_rad = 0, tilt_rad = 0;  // from looking straight ahead; tilt > 0 looks down
  int samples_per_axis = 3;          // supersampling: N x N rays per pixel
  double exposure = 1.3;
  double vignetting = 0.3;  // 0: none, 1: cos^4 fall-off
  double read_noise = 1.5;  // grey levels
  double shot_noise = 0.3;  // grey levels per sqrt(grey level)
  // Optics and sensor output (sim/optics.h); the defaults leave the pinhole frame unchanged.
  double focus_distance_m = 0;     // thin-lens focus (z-depth); 0: pinhole, no defocus
  double f_number = 2.8;           // aperture diameter f / N
  double pixel_pitch_m = 3.45e-6;  // focal length f = fx * pixel_pitch_m
  double exposure_time_s = 0;      // motion blur over the exposure; 0: none
  bool colour = false;             // RGB frames with per-channel water attenuation
  int jpeg_quality = 0;            // 1-100: JPEG round trip before the PNG; 0: none
};

// A velocity error added to every DVL sample taken in [t_s, t_s + duration_s): a deterministic
// spike for robustness tests (the random ones below come and go with the seed).
struct DvlSpike {
  double t_s = 0, duration_s = 0.5;
  Eigen::Vector3d velocity_B_mps = Eigen::Vector3d::Zero();
};

struct DvlConfig {
  bool enabled = true;
  double rate_hz = 4;
  Eigen::Vector3d position_B_m{0.2, 0.0, 0.1};
  double pan_rad = 0, tilt_rad = 0;  // from looking forward (DVL z along body x)
  double beam_angle_rad = 0.4363;    // 25 deg from the DVL axis
  double velocity_noise_mps = 0.005;
  double range_noise_m = 0.01;
  double max_range_m = 8;
  double dropout_probability = 0.02;
  double spike_probability = 0.005;
  double spike_mps = 0.3;
  // Systematic velocity errors (sound speed, misalignment): v_measured = (1 + scale_error) v +
  // bias.
  double scale_error = 0;
  Eigen::Vector3d bias_B_mps = Eigen::Vector3d::Zero();
  std::vector<DvlSpike> spikes;
};

struct PressureConfig {
  bool enabled = true;
  double rate_hz = 10;
  double noise_m = 0.01, bias_m = 0.02;
};

struct AttitudeConfig {
  bool enabled = true;
  double rate_hz = 20;
  double noise_rad = 0.003;
};

// A pose in net coordinates: `along_m` is the arc length along the net (azimuth * radius for a
// cylinder, the horizontal position for a plane), `net_distance_m` the body origin's distance
// from the undeformed net, heading 0 = facing the net squarely, heading > 0 = turned right.
struct Waypoint {
  double t_s = 0, along_m = 0, net_distance_m = 1, depth_m = 3;
  double heading_rad = 0, pitch_rad = 0, roll_rad = 0;
};

inline constexpr size_t kMaxBulges = 8, kMaxLamps = 4, kMaxFish = 8, kMaxNetChanges = 64;

// From t_s (since the start) on, the camera sees another net: a new panel, a diamond section, a
// frame from another pen. The mesh changes (type, opening angle, twines, knots, fouling, ropes,
// seams); the bar length, the scene's prior, and the wall's shape (bulges) stay.
struct NetChange {
  double t_s = 0;
  NetConfig net;
};

struct Scenario {
  std::string name;  // file stem
  std::filesystem::path file;
  uint64_t seed = 1;
  int64_t start_time_ns = 1'600'000'000'000'000'000;
  double duration_s = 0;  // default: the last waypoint's time
  CameraConfig camera;
  PenConfig pen;
  NetConfig net;
  WaterConfig water;
  LightConfig light;
  std::vector<Fish> fish;
  std::vector<NetChange> net_changes;  // sorted by time; `net` holds until the first
  DvlConfig dvl;
  PressureConfig pressure;
  AttitudeConfig attitude;
  std::vector<Waypoint> waypoints;  // sorted by time, at least one
  // The closed loop's mission and controller (`pensight closed-loop`); the trajectory then gives
  // only the start pose and duration_s the length of the run.
  std::optional<control::ControlConfig> control;
  // The simulated BlueROV2 Heavy of the closed loop; its current's mean is water.current_mps.
  vehicle::VehicleParams vehicle;

  int num_frames() const;
  int64_t frame_time_ns(int frame) const;
  SceneConfig scene_config() const;
  // The net in view at t_s (since the start): `net`, or the latest change at or before t_s.
  const NetConfig& net_at(double t_s) const;
  // That net's place: 0 for `net`, k for net_changes[k - 1]; a renderer rebuilds when it moves.
  size_t net_index_at(double t_s) const;
  // This scenario with net_at(t_s) as its one net (no changes), for what renders or scores one
  // frame.
  Scenario with_net_at(double t_s) const;
};

// Parses and validates; throws pensight::Error naming the file and key for a typo, a missing
// file, a bad value or an impossible set-up (camera outside the pen, negative radius, ...).
Scenario load_scenario(const std::filesystem::path& file);
Scenario parse_scenario(const std::string& yaml_text, const std::string& file_name);

// Markdown rows (core/params.h's param_table_rows) of every number and flag of a scenario, each
// key with its section path as in the YAML (net.ropes.width_m, light.lamps[].intensity). What the
// rows cannot say stays an explicit check of the parser or of validate():
//  - seed: a whole number; start_time_ns: a whole number of 64 bits (read as such, not a row);
//  - duration_s, when absent the waypoints' span, is held to the same range;
//  - camera.focus_distance_m: 0 or more than 2 fx * pixel_pitch_m; camera.exposure_time_s: at
//    most 1 / rate_hz;
//  - net_changes: times increase within (0, duration_s]; each change's net starts from the net
//    before it and may not set mesh_m or bulges;
//  - net.twine_width_m below 0.35 mesh_m, net.knot_size_m below 0.6 mesh_m, net.seam_spacing_m 0
//    or at least 2 mesh_m, net.ropes.spacing_m 0 or at least 4 width_m;
//  - trajectory.lawnmower: depth_to_m not above depth_from_m, at most 1000 rows; waypoint times
//    increase; the trajectory keeps the camera inside the pen (validate).
// The lists and vectors (resolution, position_m, current_mps, ...) and the names (shape,
// mesh_type, knot_shape) are checked where they are read; the control section has its own rows
// (control::control_param_rows).
std::string scenario_param_rows();

// Checks what cannot be checked key by key (the trajectory stays inside the pen, ...). Called
// by the loaders; call it again after changing a Scenario in code.
void validate(const Scenario& s);

}  // namespace pensight::sim
