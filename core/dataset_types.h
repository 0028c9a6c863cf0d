#pragma once
// Value types of the dataset contract (../shared/dataset-format.md, version 1). Timestamps are
// integer nanoseconds shared by all sensors; frames and signs are those of the contract.
#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "core/camera.h"
#include "core/units.h"

namespace pensight {

// cam0/sensor.yaml.
struct CameraCalibration {
  PinholeCamera camera;
  Eigen::Isometry3d T_body_camera = Eigen::Isometry3d::Identity();  // sensor.yaml T_BS
  double rate_hz = 10.0;
};

// How the mesh hangs in the net wall (dataset-format.md): square = bars along the wall's
// horizontal and vertical, diamond = bars at +-angle/2 from the vertical.
enum class MeshType { kSquare, kDiamond };
const char* to_string(MeshType type);  // "square" | "diamond", as in scene.yaml
// The type that to_string() names `name`; nullopt for any other text.
std::optional<MeshType> parse_mesh_type(const std::string& name);

// The pen radius a config holds until scene.yaml (where it is required) or a scenario sets it.
inline constexpr double kDefaultPenRadius_m = 12.0;

// scene.yaml.
struct SceneConfig {
  double bar_length_m = 0.030;                // bar length: knot to knot
  double pen_radius_m = kDefaultPenRadius_m;  // a flat net is a large radius (e.g. 100)
  std::optional<double> initial_rho_rad;
  // Optional (contract 1.1): a prior for the detector, which estimates what is absent.
  std::optional<MeshType> net_mesh_type;
  std::optional<double> net_mesh_angle_rad;  // nominal opening angle; scene.yaml has degrees
  // Optional (contract 1.1): the net wall's shape. A flat panel is the vertical plane through
  // `plane_point_m` (P) with the unit horizontal normal `plane_normal` pointing away from the
  // camera side; pen_radius_m still names the equivalent cylinder.
  struct FlatPanel {
    Eigen::Vector3d plane_point_m = Eigen::Vector3d::Zero();
    Eigen::Vector3d plane_normal = Eigen::Vector3d::UnitX();
  };
  std::optional<FlatPanel> flat_panel;  // nullopt: net_type cylinder
};

// The net wall's horizontal curvature: 1 / pen_radius_m, 0 on a flat panel.
double net_curvature_per_m(const SceneConfig& scene);

// One line of cam0/data.csv; the image is cam0/data/<filename>, the ground-truth depth (when
// present) groundtruth0/depth/<filename>.
struct ImageEntry {
  int64_t timestamp_ns = 0;
  std::string filename;
};

// dvl0/sensor.yaml.
struct DvlCalibration {
  Eigen::Isometry3d T_body_dvl = Eigen::Isometry3d::Identity();  // sensor.yaml T_BS
  std::array<Eigen::Vector3d, 4> beam_directions_S;              // unit vectors in the DVL frame
  double rate_hz = 4.0;
};

// One line of dvl0/data.csv. The velocity is the body-frame velocity over the ground/net.
struct DvlSample {
  int64_t timestamp_ns = 0;
  Eigen::Vector3d velocity_B_mps = Eigen::Vector3d::Zero();
  bool valid = false;
  std::array<double, 4> beam_range_m = {kNaN, kNaN, kNaN, kNaN};  // NaN: no return / not recorded
  std::optional<int64_t> device_ns;  // a live device's own time stamp of the sample (raw)
};

// One line of pressure0/data.csv.
struct PressureSample {
  int64_t timestamp_ns = 0;
  double depth_m = 0;                // positive below the surface
  std::optional<int64_t> device_ns;  // a live device's own time stamp of the sample (raw)
};

// One line of imu0/attitude.csv: body attitude in the pen frame P.
struct AttitudeSample {
  int64_t timestamp_ns = 0;
  double roll_rad = 0, pitch_rad = 0, yaw_rad = 0;
  std::optional<int64_t> device_ns;  // a live device's own time stamp of the sample (raw)
};

// One line of groundtruth0/data.csv: body pose in the pen frame, net values for cam0 (NaN where
// the optical axis misses the net).
struct GroundTruthRow {
  int64_t timestamp_ns = 0;
  Eigen::Vector3d p_pen_body_m = Eigen::Vector3d::Zero();
  double roll_rad = 0, pitch_rad = 0, yaw_rad = 0;
  double d_net_m = kNaN, psi_net_rad = kNaN, pitch_net_rad = kNaN;
  double net_fraction = 0;  // share of pixels that see net
};

// Rotation body -> pen (R_pen_body) from the contract's roll, pitch, yaw (Z-Y-X, yaw about +z
// down).
inline Eigen::Matrix3d rotation_from_rpy(double roll_rad, double pitch_rad, double yaw_rad) {
  return (Eigen::AngleAxisd(yaw_rad, Eigen::Vector3d::UnitZ()) *
          Eigen::AngleAxisd(pitch_rad, Eigen::Vector3d::UnitY()) *
          Eigen::AngleAxisd(roll_rad, Eigen::Vector3d::UnitX()))
      .toRotationMatrix();
}

// The inverse: roll, pitch, yaw of R_pen_body, pitch in [-pi/2, pi/2]. At pitch +-pi/2 roll and yaw
// share one angle and roll is reported as 0.
inline Eigen::Vector3d rpy_from_rotation(const Eigen::Matrix3d& R) {
  const double pitch = std::asin(std::clamp(-R(2, 0), -1.0, 1.0));
  if (std::abs(R(2, 0)) > 1 - 1e-12) return {0.0, pitch, std::atan2(-R(0, 1), R(1, 1))};
  return {std::atan2(R(2, 1), R(2, 2)), pitch, std::atan2(R(1, 0), R(0, 0))};
}

}  // namespace pensight
