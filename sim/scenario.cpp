#include "sim/scenario.h"

#include <Eigen/Geometry>
#include <cmath>
#include <fstream>
#include <numbers>
#include <optional>
#include <span>
#include <sstream>

#include "control/control_config.h"
#include "core/camera.h"
#include "core/error.h"
#include "core/params.h"
#include "core/strict_yaml.h"
#include "core/units.h"
#include "pipeline/dataset/sensor_mounts.h"

namespace pensight::sim {
namespace {

constexpr double kPi = std::numbers::pi;

// The numbers of each section, in a table beside the struct that holds them (core/params.h). A
// rule that ties two keys together stays an explicit check in the section's parser (the list is
// at scenario_param_rows in scenario.h).

// The top level's numbers as written. The seed, a whole number up to 9e15, is beyond a Param's
// int (Scenario holds it as uint64); an absent duration_s (NaN) is the trajectory's span.
struct TopLevelKeys {
  double seed = 1;
  double duration_s = kNaN;
};

// Six hours: 216 000 frames at 10 Hz, and a bound on what the trajectory checks walk through.
const Param<TopLevelKeys> kTopLevelParams[] = {
    {"seed", &TopLevelKeys::seed, "", closed_range(0, 9e15),
     "random seed of the noise, net deformation and current; a whole number"},
    {"duration_s", &TopLevelKeys::duration_s, "s", closed_range(0, 21600),
     "length of the run; absent: the trajectory's span"},
};

const Param<CameraCalibration> kCalibrationParams[] = {
    {"rate_hz", &CameraCalibration::rate_hz, "Hz", closed_range(0.1, 1000), "frame rate"},
};

const Param<CameraConfig> kCameraParams[] = {
    {"pan_rad", &CameraConfig::pan_rad, "rad", closed_range(-kPi, kPi),
     "from looking straight ahead; right > 0"},
    {"tilt_rad", &CameraConfig::tilt_rad, "rad", closed_range(-1.5, 1.5),
     "from looking straight ahead; down > 0"},
    {"samples_per_axis", &CameraConfig::samples_per_axis, "", closed_range(1, 8),
     "supersampling: N x N rays per pixel"},
    {"exposure", &CameraConfig::exposure, "", kPositive,
     "sensor gain: grey level 255 x this per unit radiance"},
    {"vignetting", &CameraConfig::vignetting, "", closed_range(0, 1),
     "vignetting; 0: none, 1: cos^4 fall-off"},
    {"read_noise", &CameraConfig::read_noise, "", closed_range(0, 100),
     "read noise in grey levels"},
    {"shot_noise", &CameraConfig::shot_noise, "", closed_range(0, 10),
     "shot noise in grey levels per sqrt(grey level)"},
    {"f_number", &CameraConfig::f_number, "", closed_range(0.5, 64), "aperture diameter f / N"},
    {"pixel_pitch_m", &CameraConfig::pixel_pitch_m, "m", closed_range(0.5e-6, 50e-6),
     "focal length f = fx * pixel_pitch_m"},
    {"focus_distance_m", &CameraConfig::focus_distance_m, "m", closed_range(0, 1000),
     "thin-lens focus (z-depth), > 2 f; 0: pinhole, no defocus"},
    {"exposure_time_s", &CameraConfig::exposure_time_s, "s", closed_range(0, 1),
     "motion blur over the exposure, <= 1 / rate_hz; 0: none"},
    {"colour", &CameraConfig::colour, "", {}, "RGB frames with per-channel water attenuation"},
    {"jpeg_quality", &CameraConfig::jpeg_quality, "", closed_range(0, 100),
     "1-100: JPEG round trip before the PNG; 0: none"},
};

const Param<PenConfig> kPenParams[] = {
    {"radius_m", &PenConfig::radius_m, "m", kPositive,
     "cylinder radius; plane: the net is the plane x = radius_m"},
    {"depth_m", &PenConfig::depth_m, "m", kPositive,
     "cylinder: depth of the wall's lower edge and of the bottom"},
    {"bottom", &PenConfig::bottom, "", {}, "cylinder: flat bottom net at depth_m"},
    {"width_m", &PenConfig::width_m, "m", kPositive, "plane: net width, centred at along = 0"},
    {"top_m", &PenConfig::top_m, "m", closed_range(0, 1000), "plane: depth of the net's top"},
    {"height_m", &PenConfig::height_m, "m", kPositive, "plane: net height below top_m"},
    {"wall_gap_m", &PenConfig::wall_gap_m, "m", closed_range(0, 1000),
     "plane: basin wall this far behind the net; 0: open water"},
    {"wall_albedo", &PenConfig::wall_albedo, "", closed_range(0, 1), "plane: basin wall albedo"},
};

const Param<NetConfig> kNetParams[] = {
    {"mesh_m", &NetConfig::bar_length_m, "m", kPositive, "bar length, knot to knot"},
    {"opening_angle_deg", &NetConfig::opening_angle_deg, "deg", closed_range(45, 135),
     "angle between the bars"},
    {"opening_angle_variation_deg", &NetConfig::opening_angle_variation_deg, "deg",
     closed_range(0, 10), "slow deformation: the angle varies by about +-this"},
    {"stretch_variation", &NetConfig::stretch_variation, "", closed_range(0, 0.05),
     "slow deformation: the bar length varies by about +-this share"},
    {"deform_scale_m", &NetConfig::deform_scale_m, "m", closed_range(0.2, 100),
     "wavelength of the deformation"},
    {"twine_width_m", &NetConfig::twine_width_m, "m", kPositive,
     "perpendicular to the twine, < 0.35 mesh_m"},
    {"knot_size_m", &NetConfig::knot_size_m, "m", closed_range(0, 1),
     "knots at the crossings, < 0.6 mesh_m; 0: knotless"},
    {"albedo", &NetConfig::albedo, "", closed_range(0, 1), "twine albedo"},
    {"fouling", &NetConfig::fouling, "", closed_range(0, 1),
     "depth of the slowly varying albedo loss"},
    {"fouling_scale_m", &NetConfig::fouling_scale_m, "m", kPositive,
     "size of the fouling's variation and patches"},
    {"fouling_coverage", &NetConfig::fouling_coverage, "", closed_range(0, 0.7),
     "share of the net in fouled patches"},
    {"seam_spacing_m", &NetConfig::seam_spacing_m, "m", closed_range(0, 1000),
     "vertical lacing lines every this, >= 2 mesh_m; 0: none"},
};

const Param<RopeConfig> kRopeParams[] = {
    {"spacing_m", &RopeConfig::spacing_m, "m", closed_range(0, 1000),
     "rope grid over the net, >= 4 width_m; 0: no ropes"},
    {"width_m", &RopeConfig::width_m, "m", closed_range(0.001, 0.2), "rope width"},
    {"albedo", &RopeConfig::albedo, "", closed_range(0, 1), "rope albedo"},
};

const Param<Bulge> kBulgeParams[] = {
    {.key = "along_m",
     .member = &Bulge::along_m,
     .unit = "m",
     .range = kAnyNumber,
     .help = "centre's arc length along the net",
     .required = true},
    {.key = "depth_m",
     .member = &Bulge::depth_m,
     .unit = "m",
     .range = kAnyNumber,
     .help = "centre's depth",
     .required = true},
    {"amplitude_m", &Bulge::amplitude_m, "m", closed_range(-5, 5),
     "Gaussian dent, > 0 pushes the net into the pen"},
    {"radius_m", &Bulge::radius_m, "m", kPositive,
     "the dent's standard deviation; a fold's half width"},
    {"fold", &Bulge::fold, "", kAnyNumber,
     "a vertical fold at along_m instead of a dent (depth_m unused; slope amplitude_m / radius_m "
     "at most 0.5)"},
};

const Param<WaterConfig> kWaterParams[] = {
    {"attenuation_per_m", &WaterConfig::attenuation_per_m, "1/m", closed_range(0.01, 20),
     "beam attenuation c, Beer-Lambert"},
    {"diffuse_attenuation_per_m", &WaterConfig::diffuse_attenuation_per_m, "1/m",
     closed_range(0, 20), "Kd: ambient light falls off as exp(-Kd z)"},
    {"backscatter", &WaterConfig::backscatter, "", closed_range(0, 10),
     "veiling light, as a share of the ambient light"},
    {"lamp_backscatter", &WaterConfig::lamp_backscatter, "", closed_range(0, 10),
     "veiling light from the lamps, per unit intensity"},
    {"marine_snow", &WaterConfig::marine_snow, "", closed_range(0, 1),
     "particles in view per 24x24 px of a 720x540, fx = 462 image"},
    {"snow_brightness", &WaterConfig::snow_brightness, "", closed_range(0, 10),
     "marine snow particle brightness"},
};

const Param<LightConfig> kLightParams[] = {
    {"ambient", &LightConfig::ambient, "", closed_range(0, 100),
     "irradiance just below the surface; 0: night"},
    {"surface_brightness", &LightConfig::surface_brightness, "", closed_range(0, 100),
     "the surface seen from below, relative to ambient"},
    {"lamp_level", &LightConfig::lamp_level, "", closed_range(0, 1), "dimmer for all lamps"},
};

const Param<Lamp> kLampParams[] = {
    {"intensity", &Lamp::intensity, "", closed_range(0, 1000),
     "irradiance at 1 m on the axis, in clear water"},
    {"half_angle_rad", &Lamp::half_angle_rad, "rad", closed_range(0.01, 1.5),
     "half intensity at this angle off the axis"},
};

const Param<Fish> kFishParams[] = {
    {"net_distance_m", &Fish::net_distance_m, "m", kPositive, "swims this far from the net"},
    {"depth_m", &Fish::depth_m, "m", kPositive, "swimming depth"},
    {"speed_mps", &Fish::speed_mps, "m/s", closed_range(-10, 10), "along the net"},
    {"along_m", &Fish::along_m, "m", kAnyNumber, "arc length along the net at the start"},
    {"length_m", &Fish::length_m, "m", kPositive, "ellipsoid length"},
    {"thickness_m", &Fish::thickness_m, "m", kPositive, "ellipsoid thickness"},
    {"albedo", &Fish::albedo, "", closed_range(0, 1), "fish albedo"},
};

const Param<DvlConfig> kDvlParams[] = {
    {"enabled", &DvlConfig::enabled, "", {}, "DVL samples in the dataset"},
    {"rate_hz", &DvlConfig::rate_hz, "Hz", closed_range(0.1, 100), "sample rate"},
    {"pan_rad", &DvlConfig::pan_rad, "rad", closed_range(-kPi, kPi),
     "mount, from looking forward: DVL z along body x"},
    {"tilt_rad", &DvlConfig::tilt_rad, "rad", closed_range(-kPi, kPi),
     "mount, from looking forward"},
    {"beam_angle_rad", &DvlConfig::beam_angle_rad, "rad", closed_range(0, 1.2),
     "beams' angle from the DVL axis"},
    {"velocity_noise_mps", &DvlConfig::velocity_noise_mps, "m/s", closed_range(0, 10),
     "white noise per velocity component"},
    {"range_noise_m", &DvlConfig::range_noise_m, "m", closed_range(0, 10),
     "white noise per beam range"},
    {"max_range_m", &DvlConfig::max_range_m, "m", kPositive,
     "a beam hitting the net farther returns nothing"},
    {"dropout_probability", &DvlConfig::dropout_probability, "", closed_range(0, 1),
     "share of samples lost"},
    {"spike_probability", &DvlConfig::spike_probability, "", closed_range(0, 1),
     "share of samples with a random spike"},
    {"spike_mps", &DvlConfig::spike_mps, "m/s", closed_range(0, 100), "size of the random spikes"},
    {"scale_error", &DvlConfig::scale_error, "", closed_range(-0.5, 0.5),
     "v_measured = (1 + scale_error) v + bias"},
};

const Param<DvlSpike> kDvlSpikeParams[] = {
    {"t_s", &DvlSpike::t_s, "s", closed_range(0, 1e6), "start of an injected velocity error"},
    {"duration_s", &DvlSpike::duration_s, "s", kPositive, "how long the injected error lasts"},
};

const Param<PressureConfig> kPressureParams[] = {
    {"enabled", &PressureConfig::enabled, "", {}, "depth samples in the dataset"},
    {"rate_hz", &PressureConfig::rate_hz, "Hz", closed_range(0.1, 1000), "sample rate"},
    {"noise_m", &PressureConfig::noise_m, "m", closed_range(0, 10), "white depth noise"},
    {"bias_m", &PressureConfig::bias_m, "m", closed_range(-10, 10), "constant depth offset"},
};

const Param<AttitudeConfig> kAttitudeParams[] = {
    {"enabled", &AttitudeConfig::enabled, "", {}, "attitude samples in the dataset"},
    {"rate_hz", &AttitudeConfig::rate_hz, "Hz", closed_range(0.1, 1000), "sample rate"},
    {"noise_rad", &AttitudeConfig::noise_rad, "rad", closed_range(0, 1), "white noise per angle"},
};

const Param<Waypoint> kWaypointParams[] = {
    {.key = "t_s",
     .member = &Waypoint::t_s,
     .unit = "s",
     .range = kAnyNumber,
     .help = "time, increasing along the list",
     .required = true},
    {"along_m", &Waypoint::along_m, "m", kAnyNumber, "arc length along the net"},
    {.key = "net_distance_m",
     .member = &Waypoint::net_distance_m,
     .unit = "m",
     .range = kAnyNumber,
     .help = "body origin's distance from the undeformed net",
     .required = true},
    {.key = "depth_m",
     .member = &Waypoint::depth_m,
     .unit = "m",
     .range = kAnyNumber,
     .help = "body origin's depth",
     .required = true},
    {"heading_rad", &Waypoint::heading_rad, "rad", kAnyNumber,
     "0: facing the net squarely, > 0: turned right"},
    {"pitch_rad", &Waypoint::pitch_rad, "rad", closed_range(-1.5, 1.5), "nose up > 0"},
    {"roll_rad", &Waypoint::roll_rad, "rad", closed_range(-1.5, 1.5), "right side down > 0"},
};

// The numbers of trajectory.lawnmower (its net_distances_m is a list).
struct Lawnmower {
  double depth_from_m = 0, depth_to_m = 0;
  double row_spacing_m = 0.5, row_length_m = 3.0, speed_mps = 0.3, along_m = 0;
};

const Param<Lawnmower> kLawnmowerParams[] = {
    {.key = "depth_from_m",
     .member = &Lawnmower::depth_from_m,
     .unit = "m",
     .range = kAnyNumber,
     .help = "depth of the first row",
     .required = true},
    {.key = "depth_to_m",
     .member = &Lawnmower::depth_to_m,
     .unit = "m",
     .range = kAnyNumber,
     .help = "rows down to this depth, not above depth_from_m",
     .required = true},
    {"row_spacing_m", &Lawnmower::row_spacing_m, "m", kPositive,
     "rows step down by this; at most 1000 rows"},
    {"row_length_m", &Lawnmower::row_length_m, "m", kPositive, "length of a row along the net"},
    {"speed_mps", &Lawnmower::speed_mps, "m/s", kPositive, "speed along rows and between them"},
    {"along_m", &Lawnmower::along_m, "m", kAnyNumber, "where the rows start along the net"},
};

// What a scenario may change of the BlueROV2 Heavy's defaults, in the ranges of
// vehicle::check_params.
const Param<vehicle::CurrentParams> kVehicleCurrentParams[] = {
    {"current_variation_mps", &vehicle::CurrentParams::variation_mps, "m/s", kNonNegative,
     "Gauss-Markov current variation per horizontal axis"},
    {"current_time_constant_s", &vehicle::CurrentParams::time_constant_s, "s", kPositive,
     "time constant of the current's variation"},
};

const Param<vehicle::AutopilotParams> kVehicleAutopilotParams[] = {
    {"pilot_gain",
     &vehicle::AutopilotParams::pilot_gain,
     "",
     {0, 1, true, false},
     "ArduSub's joystick gain"},
};

const Param<vehicle::HullParams> kVehicleHullParams[] = {
    {"water_density_kgpm3", &vehicle::HullParams::water_density_kgpm3, "kg/m^3", kPositive,
     "sea water density; 1007.5: neutrally buoyant"},
};

// The defaults of the rows of this file's own structs, as constants: GCC 12 warns falsely
// (-Wmaybe-uninitialized) on a temporary of them read through param_table_rows.
constexpr TopLevelKeys kTopLevelDefaults;
constexpr Lawnmower kLawnmowerDefaults;

Eigen::Vector3d vec3(const YamlMap& y, const std::string& key, const Eigen::Vector3d& fallback) {
  if (!y.has(key)) return fallback;
  const auto v = y.numbers(key, 3);
  return {v[0], v[1], v[2]};
}

CameraConfig parse_camera(const YamlMap& y) {
  CameraConfig c;
  PinholeCamera& k = c.calibration.camera;
  read_params(y, kCalibrationParams, c.calibration);
  if (y.has("resolution")) {
    const auto r = y.numbers("resolution", 2);
    if (r[0] < 8 || r[1] < 8 || r[0] > 8192 || r[1] > 8192 || r[0] != std::round(r[0]) ||
        r[1] != std::round(r[1])) {
      y.fail("resolution", "expected [width, height], whole pixels between 8 and 8192");
    }
    k.width_px = static_cast<int>(r[0]);
    k.height_px = static_cast<int>(r[1]);
  }
  if (y.has("intrinsics")) {
    const auto i = y.numbers("intrinsics", 4);
    if (!(i[0] > 0 && i[1] > 0)) y.fail("intrinsics", "focal lengths must be positive");
    k.fx_px = i[0];
    k.fy_px = i[1];
    k.cx_px = i[2];
    k.cy_px = i[3];
  } else {
    // Defaults scale the default camera's focal length with the width; principal point at the
    // centre.
    k.fx_px = k.fy_px = kDefaultFocalLength_px * k.width_px / kDefaultImageWidth_px;
    k.cx_px = (k.width_px - 1) / 2.0;
    k.cy_px = (k.height_px - 1) / 2.0;
  }
  if (y.has("distortion")) {
    const auto d = y.numbers("distortion", 4);
    k.k1 = d[0];
    k.k2 = d[1];
    k.p1 = d[2];
    k.p2 = d[3];
  }
  c.position_B_m = vec3(y, "position_m", c.position_B_m);
  read_params(y, kCameraParams, c);
  // The thin-lens blur circle needs the focus beyond the focal length (and a real lens focuses
  // no closer than a few focal lengths).
  const double focal_m = k.fx_px * c.pixel_pitch_m;
  if (c.focus_distance_m > 0 && !(c.focus_distance_m > 2 * focal_m)) {
    y.fail("focus_distance_m",
           "must be 0 (pinhole) or more than twice the focal length fx * "
           "pixel_pitch_m = " +
               std::to_string(focal_m) + " m");
  }
  if (!(c.exposure_time_s * c.calibration.rate_hz <= 1)) {
    y.fail("exposure_time_s", "must not be longer than the frame interval 1 / rate_hz");
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
  read_params(y, kPenParams, p);
  y.check_unknown_keys();
  return p;
}

// `base`: the net that keys absent here keep (a change starts from the net before it).
NetConfig parse_net(const YamlMap& y, NetConfig n = {}) {
  read_params(y, kNetParams, n);
  const std::string type = y.string("mesh_type", to_string(n.mesh_type));
  const std::optional<MeshType> mesh_type = parse_mesh_type(type);
  if (!mesh_type) y.fail("mesh_type", "must be 'square' or 'diamond', got '" + type + "'");
  n.mesh_type = *mesh_type;
  // Up to 30 % of the bar (heavy twine on a small mesh); the holes stay open at 45 degrees.
  if (n.twine_width_m >= 0.35 * n.bar_length_m) {
    y.fail("twine_width_m", "must be less than 0.35 * mesh_m");
  }
  if (n.knot_size_m >= 0.6 * n.bar_length_m)
    y.fail("knot_size_m", "must be less than 0.6 * mesh_m");
  const std::string knot =
      y.string("knot_shape", n.knot_shape == KnotShape::kRound ? "round" : "square");
  if (knot == "square") {
    n.knot_shape = KnotShape::kSquare;
  } else if (knot == "round") {
    n.knot_shape = KnotShape::kRound;
  } else {
    y.fail("knot_shape", "must be 'square' or 'round', got '" + knot + "'");
  }
  if (const auto r = y.optional_map("ropes")) {
    read_params(*r, kRopeParams, n.ropes);
    if (n.ropes.spacing_m > 0 && n.ropes.spacing_m < 4 * n.ropes.width_m) {
      r->fail("spacing_m", "must be 0 (no ropes) or at least 4 * width_m");
    }
    r->check_unknown_keys();
  }
  if (n.seam_spacing_m > 0 && n.seam_spacing_m < 2 * n.bar_length_m) {
    y.fail("seam_spacing_m", "must be 0 (no seams) or at least 2 * mesh_m");
  }
  if (const auto list = y.optional_map_list("bulges")) {
    if (list->size() > kMaxBulges) y.fail("bulges", "at most 8 bulges");
    for (const YamlMap& b : *list) {
      Bulge g;
      read_params(b, kBulgeParams, g);
      if (g.fold && std::abs(g.amplitude_m) > kMaxFoldSlope * g.radius_m) {
        b.fail("amplitude_m", "a fold's slope amplitude_m / radius_m must be at most 0.5");
      }
      b.check_unknown_keys();
      n.bulges.push_back(g);
    }
  }
  y.check_unknown_keys();
  return n;
}

WaterConfig parse_water(const YamlMap& y) {
  WaterConfig w;
  read_params(y, kWaterParams, w);
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
  read_params(y, kLightParams, l);
  if (const auto list = y.optional_map_list("lamps")) {
    if (list->size() > kMaxLamps) y.fail("lamps", "at most 4 lamps");
    for (const YamlMap& m : *list) {
      Lamp lamp;
      lamp.position_B_m = vec3(m, "position_m", lamp.position_B_m);
      lamp.direction_B = vec3(m, "direction", lamp.direction_B);
      if (!(lamp.direction_B.norm() > 1e-6)) m.fail("direction", "must not be zero");
      lamp.direction_B.normalize();
      read_params(m, kLampParams, lamp);
      m.check_unknown_keys();
      l.lamps.push_back(lamp);
    }
  } else {
    l.lamps = default_lamps();
  }
  y.check_unknown_keys();
  return l;
}

const Param<NetChange> kNetChangeParams[] = {
    {.key = "t_s",
     .member = &NetChange::t_s,
     .unit = "s",
     .range = closed_range(0, 21600),
     .help = "from this time on (since the start) the camera sees the change's net",
     .required = true},
};

// Each change's `net:` table starts from the net before it, so it names only what changes.
std::vector<NetChange> parse_net_changes(const YamlMap& y, const NetConfig& first) {
  std::vector<NetChange> out;
  const auto list = y.optional_map_list("net_changes");
  if (!list) return out;
  if (list->size() > kMaxNetChanges) y.fail("net_changes", "at most 64 changes");
  const NetConfig* before = &first;
  for (const YamlMap& m : *list) {
    NetChange c;
    read_params(m, kNetChangeParams, c);
    if (!out.empty() && c.t_s <= out.back().t_s)
      m.fail("t_s", "must increase from change to change");
    if (c.t_s <= 0) m.fail("t_s", "must be after the start (the first net is `net:`)");
    const YamlMap net = m.map("net");
    if (net.has("mesh_m")) {
      net.fail("mesh_m", "stays the first net's: the bar length is the scene's prior");
    }
    if (net.has("bulges")) net.fail("bulges", "stay the first net's: the wall keeps its shape");
    c.net = parse_net(net, *before);
    m.check_unknown_keys();
    out.push_back(c);
    before = &out.back().net;
  }
  return out;
}

std::vector<Fish> parse_fish(const YamlMap& y) {
  std::vector<Fish> out;
  const auto list = y.optional_map_list("fish");
  if (!list) return out;
  if (list->size() > kMaxFish) y.fail("fish", "at most 8 fish");
  for (const YamlMap& m : *list) {
    Fish f;
    read_params(m, kFishParams, f);
    m.check_unknown_keys();
    out.push_back(f);
  }
  return out;
}

DvlConfig parse_dvl(const YamlMap& y) {
  DvlConfig d;
  read_params(y, kDvlParams, d);
  d.position_B_m = vec3(y, "position_m", d.position_B_m);
  d.bias_B_mps = vec3(y, "bias_mps", d.bias_B_mps);
  if (const auto list = y.optional_map_list("spikes")) {
    for (const YamlMap& m : *list) {
      DvlSpike spike;
      read_params(m, kDvlSpikeParams, spike);
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
  read_params(y, kPressureParams, p);
  y.check_unknown_keys();
  return p;
}

AttitudeConfig parse_attitude(const YamlMap& y) {
  AttitudeConfig a;
  read_params(y, kAttitudeParams, a);
  y.check_unknown_keys();
  return a;
}

Waypoint parse_waypoint(const YamlMap& m) {
  Waypoint w;
  read_params(m, kWaypointParams, w);
  m.check_unknown_keys();
  return w;
}

// Passes along the net at each distance: horizontal rows stepping down by row_spacing_m,
// alternating direction, with straight moves between rows and distances.
std::vector<Waypoint> lawnmower(const YamlMap& y) {
  const std::vector<double> distances = y.numbers("net_distances_m");
  if (distances.empty()) y.fail("net_distances_m", "needs at least one distance");
  Lawnmower mower;
  read_params(y, kLawnmowerParams, mower);
  const double top = mower.depth_from_m, bottom = mower.depth_to_m, spacing = mower.row_spacing_m;
  if (!(bottom >= top)) y.fail("depth_to_m", "must not be above depth_from_m");
  if (!((bottom - top) / spacing <= 1000)) y.fail("row_spacing_m", "more than 1000 rows");
  y.check_unknown_keys();
  const int rows = static_cast<int>(std::floor((bottom - top) / spacing + 1e-9)) + 1;
  std::vector<Waypoint> out;
  double t = 0;
  auto go = [&](double along, double dist, double depth) {
    if (!out.empty()) {
      const Waypoint& p = out.back();
      t += std::hypot(along - p.along_m, dist - p.net_distance_m, depth - p.depth_m) /
           mower.speed_mps;
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
      go(forward ? mower.along_m : mower.along_m + mower.row_length_m, dist, depth);
      go(forward ? mower.along_m + mower.row_length_m : mower.along_m, dist, depth);
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
  } else {
    out = lawnmower(y.map("lawnmower"));
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

size_t Scenario::net_index_at(double t_s) const {
  // A change lands on the frame at its time, whatever the rounding of frame / rate_hz.
  constexpr double kFrameTimeSlack_s = 1e-9;
  size_t k = 0;
  while (k < net_changes.size() && net_changes[k].t_s <= t_s + kFrameTimeSlack_s) ++k;
  return k;
}

const NetConfig& Scenario::net_at(double t_s) const {
  const size_t k = net_index_at(t_s);
  return k == 0 ? net : net_changes[k - 1].net;
}

Scenario Scenario::with_net_at(double t_s) const {
  Scenario s = *this;
  s.net = net_at(t_s);
  s.net_changes.clear();
  return s;
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
  read_params(y, kVehicleCurrentParams, v.current);
  read_params(y, kVehicleAutopilotParams, v.autopilot);
  read_params(y, kVehicleHullParams, v.hull);
  y.check_unknown_keys();
}

}  // namespace

Scenario parse_scenario(const std::string& text, const std::string& file_name) {
  const YamlMap y = YamlMap::parse(text, file_name);
  Scenario s;
  s.file = file_name;
  s.name = std::filesystem::path(file_name).stem().string();
  TopLevelKeys top;
  read_params(y, kTopLevelParams, top);
  if (top.seed != std::floor(top.seed)) y.fail("seed", "must be a whole number");
  s.seed = static_cast<uint64_t>(top.seed);
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
  s.net_changes = parse_net_changes(y, s.net);
  if (const auto m = y.optional_map("dvl")) s.dvl = parse_dvl(*m);
  if (const auto m = y.optional_map("pressure")) s.pressure = parse_pressure(*m);
  if (const auto m = y.optional_map("attitude")) s.attitude = parse_attitude(*m);
  if (const auto m = y.optional_map("control")) s.control = control::parse_control_config(*m);
  if (const auto m = y.optional_map("vehicle")) parse_vehicle(*m, s.vehicle);
  s.vehicle.current.mean_pen_mps = s.water.current_mps;
  s.vehicle.current.seed = s.seed;
  s.waypoints = parse_trajectory(y.map("trajectory"));
  if (s.waypoints.empty()) y.fail("trajectory", "needs at least one waypoint");
  if (std::isnan(top.duration_s)) {
    top.duration_s = s.waypoints.back().t_s - s.waypoints.front().t_s;
    // The trajectory's span is held to the range of duration_s.
    check_params<TopLevelKeys>(top, kTopLevelParams, y.file());
  }
  s.duration_s = top.duration_s;
  if (!s.net_changes.empty() && s.net_changes.back().t_s > s.duration_s) {
    y.fail("net_changes", "the last change (t_s " + std::to_string(s.net_changes.back().t_s) +
                              ") comes after the run's end (duration_s " +
                              std::to_string(s.duration_s) + ")");
  }
  y.check_unknown_keys();
  validate(s);
  return s;
}

std::string scenario_param_rows() {
  const Scenario d;
  std::string rows = param_table_rows<TopLevelKeys>(kTopLevelParams, kTopLevelDefaults);
  rows += param_table_rows<CameraCalibration>(kCalibrationParams, d.camera.calibration, "camera.");
  rows += param_table_rows<CameraConfig>(kCameraParams, d.camera, "camera.");
  rows += param_table_rows<PenConfig>(kPenParams, d.pen, "pen.");
  rows += param_table_rows<NetConfig>(kNetParams, d.net, "net.");
  rows += param_table_rows<RopeConfig>(kRopeParams, d.net.ropes, "net.ropes.");
  rows += param_table_rows<Bulge>(kBulgeParams, Bulge{}, "net.bulges[].");
  rows += param_table_rows<WaterConfig>(kWaterParams, d.water, "water.");
  rows += param_table_rows<LightConfig>(kLightParams, d.light, "light.");
  rows += param_table_rows<Lamp>(kLampParams, Lamp{}, "light.lamps[].");
  rows += param_table_rows<Fish>(kFishParams, Fish{}, "fish[].");
  rows += param_table_rows<NetChange>(kNetChangeParams, NetChange{}, "net_changes[].");
  rows += param_table_rows<DvlConfig>(kDvlParams, d.dvl, "dvl.");
  rows += param_table_rows<DvlSpike>(kDvlSpikeParams, DvlSpike{}, "dvl.spikes[].");
  rows += param_table_rows<PressureConfig>(kPressureParams, d.pressure, "pressure.");
  rows += param_table_rows<AttitudeConfig>(kAttitudeParams, d.attitude, "attitude.");
  rows += param_table_rows<Waypoint>(kWaypointParams, Waypoint{}, "trajectory.waypoints[].");
  rows +=
      param_table_rows<Lawnmower>(kLawnmowerParams, kLawnmowerDefaults, "trajectory.lawnmower.");
  rows += param_table_rows<vehicle::CurrentParams>(kVehicleCurrentParams, d.vehicle.current,
                                                   "vehicle.");
  rows += param_table_rows<vehicle::AutopilotParams>(kVehicleAutopilotParams, d.vehicle.autopilot,
                                                     "vehicle.");
  rows += param_table_rows<vehicle::HullParams>(kVehicleHullParams, d.vehicle.hull, "vehicle.");
  return rows;
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
