#include "pipeline/fft/mesh_angle.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <numbers>
#include <vector>

#include "core/median.h"

namespace pensight {
namespace {

double angle_between(const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  return std::atan2(a.cross(b).norm(), a.dot(b));
}

}  // namespace

MeshAngleMeasurement measure_mesh_angle(std::span<const RoiNetPoint> rois,
                                        std::span<const uint8_t> use,
                                        std::span<const Eigen::Vector3d> normals_C,
                                        const PinholeCamera& camera, std::optional<MeshType> type,
                                        const MeshAngleParams& params) {
  MeshAngleMeasurement out;
  struct Cell {
    Eigen::Vector3d b1, b2;     // unit bars, b2 signed for the acute angle
    Eigen::Vector3d bisector;   // of the acute angle
    Eigen::Vector3d up, right;  // the net's, where the ROI sees it
  };
  std::vector<Cell> cells;
  std::vector<double> bisector_offsets;  // of the acute bisector from the nearest of up / right
  for (size_t i = 0; i < rois.size() && i < use.size() && i < normals_C.size(); ++i) {
    if (!use[i] || !rois[i].valid()) continue;
    const Eigen::Vector3d n = normals_C[i].normalized();
    auto bars = bars_on_plane(rois[i], camera, rois[i].p_C, n);
    const double l1 = bars[0].norm(), l2 = bars[1].norm();
    if (!(l1 > 0 && l2 > 0) || std::abs(l1 - l2) > params.max_bar_mismatch * std::max(l1, l2)) {
      continue;
    }
    Cell c{bars[0] / l1, bars[1] / l2, Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero(),
           Eigen::Vector3d::Zero()};
    if (c.b1.dot(c.b2) < 0) c.b2 = -c.b2;
    c.bisector = (c.b1 + c.b2).normalized();
    // The net's up and right in its plane there, from the camera's.
    c.up = (-Eigen::Vector3d::UnitY() + n.y() * n).normalized();
    c.right = c.up.cross(n).dot(Eigen::Vector3d::UnitX()) >= 0 ? c.up.cross(n) : n.cross(c.up);
    const double to_up = std::acos(std::min(1.0, std::abs(c.bisector.dot(c.up))));
    bisector_offsets.push_back(std::min(to_up, std::numbers::pi / 2 - to_up));
    cells.push_back(c);
  }
  if (static_cast<int>(cells.size()) < params.min_rois) return out;
  const double bisector_offset = median(bisector_offsets);
  const MeshType seen =
      bisector_offset < params.diamond_bisector_rad ? MeshType::kDiamond : MeshType::kSquare;
  const bool clear =
      std::abs(bisector_offset - params.diamond_bisector_rad) >= params.type_evidence_margin_rad;
  out.type = type && !clear ? *type : seen;
  std::vector<double> angles;
  for (const Cell& c : cells) {
    const Eigen::Vector3d reference =
        out.type == MeshType::kDiamond ? c.up : (c.up + c.right).normalized();
    // Of the cell's two angles, the one whose bisector is nearer the reference.
    const Eigen::Vector3d obtuse_bisector = (c.b1 - c.b2).normalized();
    const double acute = angle_between(c.b1, c.b2);
    angles.push_back(std::abs(c.bisector.dot(reference)) >= std::abs(obtuse_bisector.dot(reference))
                         ? acute
                         : std::numbers::pi - acute);
  }
  out.rois = static_cast<int>(angles.size());
  out.opening_angle_rad = median(angles);
  std::vector<double> deviation;
  for (double a : angles) deviation.push_back(std::abs(a - out.opening_angle_rad));
  // kMadToSigma MAD is sigma for Gaussian scatter. Not divided by sqrt(n): the ROIs share the
  // plane's normal, whose error moves all their angles alike, and a frame far and oblique reads its
  // median 2-3 deg off while claiming a tenth of that from sqrt(n).
  out.sigma_rad = kMadToSigma * median(deviation);
  return out;
}

MeshAngleFilter::MeshAngleFilter(std::optional<double> prior_rad)
    : MeshAngleFilter(prior_rad, Params{}) {}

MeshAngleFilter::MeshAngleFilter(std::optional<double> prior_rad, const Params& params)
    : params_(params) {
  if (prior_rad) state_ = {*prior_rad, params.prior_sigma_rad * params.prior_sigma_rad, 0};
  before_ = state_;
}

double MeshAngleFilter::angle_rad() const {
  return state_.var >= 0 ? state_.angle : std::numbers::pi / 2;
}

double MeshAngleFilter::update(const MeshAngleMeasurement& m) {
  if (state_.var >= 0) state_.var += params_.process_sigma_rad * params_.process_sigma_rad;
  before_ = state_;
  fuse(m);
  return angle_rad();
}

double MeshAngleFilter::refine(const MeshAngleMeasurement& m) {
  state_ = before_;
  fuse(m);
  return angle_rad();
}

void MeshAngleFilter::fuse(const MeshAngleMeasurement& m) {
  rejected_last_ = false;
  if (!m.valid()) return;
  const double sigma = std::max(m.sigma_rad, params_.min_sigma_rad);
  const double r = sigma * sigma;
  State& s = state_;
  const double innovation = m.opening_angle_rad - s.angle;
  const double gate = params_.gate_sigmas * params_.gate_sigmas * (s.var + r);
  const bool outside = s.var >= 0 && innovation * innovation > gate;
  if (s.var < 0 || (outside && ++s.outside >= params_.restart_after)) {
    s = {m.opening_angle_rad, r, 0};
    return;
  }
  if (outside) {
    rejected_last_ = true;
    return;
  }
  s.outside = 0;
  const double k = s.var / (s.var + r);
  s.angle += k * innovation;
  s.var *= 1 - k;
}

}  // namespace pensight
