#include "pipeline/dataset/calibration_yaml.h"

#include <cmath>
#include <sstream>

#include "core/csv.h"
#include "core/image.h"
#include "core/params.h"
#include "core/strict_yaml.h"
#include "core/units.h"

namespace pensight {
namespace {

std::string list(const double* v, size_t n) {
  std::string s = "[";
  for (size_t i = 0; i < n; ++i) s += (i ? ", " : "") + format_number(v[i]);
  return s + "]";
}

// A Kalibr-style matrix {cols, rows, data (row-major)}; a wrong size fails with `shape`.
Eigen::MatrixXd read_matrix(const YamlMap& parent, const std::string& key, int rows, int cols,
                            const std::string& shape) {
  const YamlMap m = parent.map(key);
  if (m.integer("rows") != rows || m.integer("cols") != cols) parent.fail(key, shape);
  const std::vector<double> data = m.numbers("data", static_cast<size_t>(rows * cols));
  m.check_unknown_keys();
  Eigen::MatrixXd out(rows, cols);
  for (int r = 0; r < rows; ++r) {
    for (int c = 0; c < cols; ++c) out(r, c) = data[static_cast<size_t>(r * cols + c)];
  }
  return out;
}

std::string matrix_yaml(const Eigen::MatrixXd& m) {
  std::vector<double> data;
  for (Eigen::Index r = 0; r < m.rows(); ++r) {
    for (Eigen::Index c = 0; c < m.cols(); ++c) data.push_back(m(r, c));
  }
  return "{cols: " + std::to_string(m.cols()) + ", rows: " + std::to_string(m.rows()) +
         ", data: " + list(data.data(), data.size()) + "}";
}

Eigen::Isometry3d read_transform(const YamlMap& parent, const std::string& key) {
  const Eigen::Matrix4d T = read_matrix(parent, key, 4, 4, "expected rows: 4, cols: 4");
  const Eigen::Matrix3d R = T.topLeftCorner<3, 3>();
  // 1e-5 leaves room for rotations printed with 6 decimals by calibration tools.
  if ((R.transpose() * R - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff() > 1e-5 ||
      std::abs(R.determinant() - 1) > 1e-5 ||
      (T.row(3) - Eigen::RowVector4d(0, 0, 0, 1)).cwiseAbs().maxCoeff() > 1e-9) {
    parent.fail(key, "not a rigid transform (rotation must be orthonormal, last row 0 0 0 1)");
  }
  Eigen::Isometry3d iso = Eigen::Isometry3d::Identity();
  iso.linear() = R;
  iso.translation() = T.topRightCorner<3, 1>();
  return iso;
}

void expect_sensor_type(const YamlMap& y, const std::string& type) {
  if (y.string("sensor_type") != type) y.fail("sensor_type", "expected '" + type + "'");
}

const Param<CameraCalibration> kCameraParams[] = {
    {.key = "rate_hz",
     .member = &CameraCalibration::rate_hz,
     .unit = "Hz",
     .range = kPositive,
     .help = "frame rate",
     .required = true},
};

const Param<DvlCalibration> kDvlParams[] = {
    {.key = "rate_hz",
     .member = &DvlCalibration::rate_hz,
     .unit = "Hz",
     .range = kPositive,
     .help = "velocity sample rate",
     .required = true},
};

// Beyond 30-150 deg the twines of a hung net would lie almost on top of each other.
const Param<SceneConfig> kSceneParams[] = {
    {.key = "net_mesh_size_m",
     .member = &SceneConfig::bar_length_m,
     .unit = "m",
     .range = kPositive,
     .help = "bar length: knot to knot",
     .required = true},
    {.key = "pen_radius_m",
     .member = &SceneConfig::pen_radius_m,
     .unit = "m",
     .range = kPositive,
     .help = "cylinder radius; a flat net is a large radius (e.g. 100)",
     .required = true},
    {.key = "net_mesh_angle_deg",
     .member = &SceneConfig::net_mesh_angle_rad,
     .unit = "deg",
     .range = closed_range(30, 150),
     .help = "nominal opening angle of the mesh (90: undeformed square); absent: estimated",
     .scale = deg_to_rad(1)},
    {.key = "initial_rho_rad",
     .member = &SceneConfig::initial_rho_rad,
     .unit = "rad",
     .range = kAnyNumber,
     .help = "rho_g at the global pose's lock (absent: 0)"},
};

// The contract allows both forms because DVL files come from other tools: a Kalibr-style matrix
// (one beam per row) or a list of 3-vectors.
Eigen::MatrixXd read_beams(const YamlMap& y) {
  const std::string key = "beam_directions";
  const std::string shape =
      "expected 4 unit vectors in the DVL frame, either as a matrix "
      "{cols: 3, rows: 4, data: [12 numbers, row-major]} or as a list "
      "[[x, y, z], [x, y, z], [x, y, z], [x, y, z]]";
  if (y.is_map(key)) return read_matrix(y, key, 4, 3, shape);
  if (!y.is_list(key)) y.fail(key, y.has(key) ? shape : "missing; add it, " + shape);
  const std::vector<std::vector<double>> rows = y.number_rows(key, 4, 3, shape);
  Eigen::MatrixXd out(4, 3);
  for (int r = 0; r < 4; ++r) {
    for (int c = 0; c < 3; ++c) out(r, c) = rows[static_cast<size_t>(r)][static_cast<size_t>(c)];
  }
  return out;
}

}  // namespace

std::string camera_param_rows() {
  return param_table_rows<CameraCalibration>(kCameraParams);
}

std::string dvl_param_rows() {
  return param_table_rows<DvlCalibration>(kDvlParams);
}

std::string scene_param_rows() {
  return param_table_rows<SceneConfig>(kSceneParams);
}

CameraCalibration read_camera_yaml(const std::filesystem::path& file) {
  const YamlMap y = YamlMap::load_file(file, UnknownKeys::kNote);
  y.string("comment", "");
  expect_sensor_type(y, "camera");
  CameraCalibration c;
  read_params<CameraCalibration>(y, kCameraParams, c);
  const auto res = y.numbers("resolution", 2);
  if (!(res[0] >= 1 && res[1] >= 1 && res[0] <= kMaxImageSide_px && res[1] <= kMaxImageSide_px) ||
      res[0] != std::round(res[0]) || res[1] != std::round(res[1])) {
    y.fail("resolution", "expected [width, height] in whole pixels, each 1 to " +
                             std::to_string(kMaxImageSide_px));
  }
  c.camera.width_px = static_cast<int>(res[0]);
  c.camera.height_px = static_cast<int>(res[1]);
  if (y.string("camera_model") != "pinhole") y.fail("camera_model", "only 'pinhole' is supported");
  const auto k = y.numbers("intrinsics", 4);
  if (!(k[0] > 0 && k[1] > 0)) y.fail("intrinsics", "focal lengths fu, fv must be positive");
  c.camera.fx_px = k[0];
  c.camera.fy_px = k[1];
  c.camera.cx_px = k[2];
  c.camera.cy_px = k[3];
  const std::string model = y.string("distortion_model");
  if (model != "radial-tangential" && model != "radtan") {
    y.fail("distortion_model", "only 'radial-tangential' (k1, k2, p1, p2) is supported");
  }
  const auto d = y.numbers("distortion_coefficients", 4);
  c.camera.k1 = d[0];
  c.camera.k2 = d[1];
  c.camera.p1 = d[2];
  c.camera.p2 = d[3];
  c.T_body_camera = read_transform(y, "T_BS");
  y.check_unknown_keys();
  return c;
}

std::string camera_yaml(const CameraCalibration& c) {
  const PinholeCamera& k = c.camera;
  const double intr[] = {k.fx_px, k.fy_px, k.cx_px, k.cy_px};
  const double dist[] = {k.k1, k.k2, k.p1, k.p2};
  std::ostringstream s;
  s << "sensor_type: camera\n"
    << "rate_hz: " << format_number(c.rate_hz) << "\n"
    << "resolution: [" << k.width_px << ", " << k.height_px << "]\n"
    << "camera_model: pinhole\n"
    << "intrinsics: " << list(intr, 4) << "  # fu, fv, cu, cv\n"
    << "distortion_model: radial-tangential\n"
    << "distortion_coefficients: " << list(dist, 4) << "  # k1, k2, p1, p2\n"
    << "T_BS: " << matrix_yaml(c.T_body_camera.matrix()) << "  # camera -> body\n";
  return s.str();
}

DvlCalibration read_dvl_yaml(const std::filesystem::path& file) {
  const YamlMap y = YamlMap::load_file(file, UnknownKeys::kNote);
  y.string("comment", "");
  expect_sensor_type(y, "dvl");
  DvlCalibration c;
  read_params<DvlCalibration>(y, kDvlParams, c);
  c.T_body_dvl = read_transform(y, "T_BS");
  const Eigen::MatrixXd beams = read_beams(y);
  for (int i = 0; i < 4; ++i) {
    const Eigen::Vector3d b = beams.row(i).transpose();
    if (std::abs(b.norm() - 1) > 1e-4) y.fail("beam_directions", "each beam must be a unit vector");
    c.beam_directions_S[static_cast<size_t>(i)] = b.normalized();
  }
  y.check_unknown_keys();
  return c;
}

std::string dvl_yaml(const DvlCalibration& c) {
  Eigen::MatrixXd beams(4, 3);
  for (int i = 0; i < 4; ++i) beams.row(i) = c.beam_directions_S[static_cast<size_t>(i)];
  std::ostringstream s;
  s << "sensor_type: dvl\n"
    << "rate_hz: " << format_number(c.rate_hz) << "\n"
    << "T_BS: " << matrix_yaml(c.T_body_dvl.matrix()) << "  # DVL -> body\n"
    << "beam_directions: " << matrix_yaml(beams) << "  # unit vectors in the DVL frame\n";
  return s.str();
}

SceneConfig read_scene_yaml(const std::filesystem::path& file) {
  const YamlMap y = YamlMap::load_file(file, UnknownKeys::kNote);
  SceneConfig s;
  read_params<SceneConfig>(y, kSceneParams, s);
  if (y.has("net_mesh_type")) {
    const std::string type = y.string("net_mesh_type");
    s.net_mesh_type = parse_mesh_type(type);
    if (!s.net_mesh_type) {
      y.fail("net_mesh_type", "'" + type + "' is not a mesh type: use square or diamond");
    }
  }
  const std::string net_type = y.string("net_type", "cylinder");
  if (net_type == "flat_panel") {
    SceneConfig::FlatPanel panel;
    const auto point = y.numbers("net_plane_point_m", 3);
    const auto normal = y.numbers("net_plane_normal", 3);
    panel.plane_point_m = Eigen::Vector3d(point[0], point[1], point[2]);
    panel.plane_normal = Eigen::Vector3d(normal[0], normal[1], normal[2]);
    // The estimators model a hanging (vertical) net: its normal lies within 10 deg of the
    // horizontal, and it is given to 1 % of unit length (a normal from another tool's fit).
    const double norm = panel.plane_normal.norm();
    if (!(std::abs(norm - 1) <= 0.01) ||
        !(std::abs(panel.plane_normal.z()) <= std::sin(deg_to_rad(10)))) {
      y.fail("net_plane_normal",
             "must be a unit vector within 10 deg of the horizontal (a hanging net), e.g. "
             "[1, 0, 0]");
    }
    panel.plane_normal.z() = 0;
    panel.plane_normal.normalize();
    // The pen frame's origin is on the camera side of the panel.
    if (!(panel.plane_normal.dot(panel.plane_point_m) > 0)) {
      y.fail("net_plane_normal",
             "must point away from the pen frame's origin (the camera side): normal . point > 0");
    }
    s.flat_panel = panel;
  } else if (net_type != "cylinder") {
    y.fail("net_type", "'" + net_type + "' is not a net type: use cylinder or flat_panel");
  }
  y.check_unknown_keys();
  return s;
}

std::string scene_yaml(const SceneConfig& s) {
  std::string out = "net_mesh_size_m: " + format_number(s.bar_length_m) + "\n" +
                    "pen_radius_m: " + format_number(s.pen_radius_m) + "\n";
  if (s.net_mesh_type) out += std::string("net_mesh_type: ") + to_string(*s.net_mesh_type) + "\n";
  if (s.net_mesh_angle_rad) {
    out += "net_mesh_angle_deg: " + format_number(rad_to_deg(*s.net_mesh_angle_rad)) + "\n";
  }
  if (s.flat_panel) {
    const auto vec = [](const Eigen::Vector3d& v) {
      std::string text = "[";
      for (int i = 0; i < 3; ++i) text.append(i ? ", " : "").append(format_number(v(i)));
      return text.append("]");
    };
    out += "net_type: flat_panel\n";
    out += "net_plane_point_m: " + vec(s.flat_panel->plane_point_m) + "\n";
    out += "net_plane_normal: " + vec(s.flat_panel->plane_normal) + "\n";
  }
  if (s.initial_rho_rad) out += "initial_rho_rad: " + format_number(*s.initial_rho_rad) + "\n";
  return out;
}

}  // namespace pensight
