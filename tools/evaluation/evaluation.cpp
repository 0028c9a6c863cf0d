#include "tools/evaluation/evaluation.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <unordered_map>
#include <vector>

#include "core/error.h"
#include "core/units.h"

namespace pensight {
namespace {

struct Estimate {
  double d_m, psi_rad, pitch_rad;
};

Estimate pick(const EstimateRow& r, NetPoseSource source) {
  return source == NetPoseSource::kFft
             ? Estimate{r.d_net_fft_m, r.psi_net_fft_rad, r.pitch_net_fft_rad}
             : Estimate{r.d_net_depth_m, r.psi_net_depth_rad, r.pitch_net_depth_rad};
}

std::unordered_map<int64_t, const GroundTruthRow*> truth_by_time(const Dataset& dataset) {
  if (!dataset.groundtruth0) {
    throw Error("dataset " + dataset.root.string() +
                " has no groundtruth0/data.csv, so estimates cannot be scored");
  }
  std::unordered_map<int64_t, const GroundTruthRow*> truth;
  for (const GroundTruthRow& t : dataset.groundtruth0->rows) truth[t.timestamp_ns] = &t;
  return truth;
}

bool inside(const GroundTruthRow& t, const AccuracyEnvelope& e) {
  return std::isfinite(t.d_net_m) && t.net_fraction >= e.min_net_fraction &&
         t.d_net_m >= e.min_d_net_m && t.d_net_m <= e.max_d_net_m &&
         std::abs(t.psi_net_rad) <= e.max_abs_psi_net_rad;
}

}  // namespace

ErrorStats error_stats(std::span<const double> errors) {
  ErrorStats s;
  s.count = errors.size();
  if (errors.empty()) return s;
  std::vector<double> v(errors.size());
  std::transform(errors.begin(), errors.end(), v.begin(), [](double x) { return std::abs(x); });
  std::sort(v.begin(), v.end());
  const auto rank = [&](double q) {
    const size_t k = static_cast<size_t>(std::ceil(q * static_cast<double>(v.size())));
    return v[std::clamp<size_t>(k, 1, v.size()) - 1];
  };
  s.median = rank(0.5);
  s.p95 = rank(0.95);
  s.max = v.back();
  return s;
}

NetPoseAccuracy score_net_pose(const Dataset& dataset, std::span<const EstimateRow> rows,
                               NetPoseSource source, const AccuracyEnvelope& envelope) {
  const auto truth = truth_by_time(dataset);
  NetPoseAccuracy a;
  std::vector<double> d_rel, psi_deg, pitch_deg;
  for (const EstimateRow& r : rows) {
    const auto it = truth.find(r.timestamp_ns);
    if (it == truth.end()) continue;
    const GroundTruthRow& t = *it->second;
    const Estimate e = pick(r, source);
    ++a.frames;
    if (std::isfinite(e.d_m) &&
        (!std::isfinite(t.d_net_m) || std::abs(e.d_m - t.d_net_m) > a.gross_rel * t.d_net_m)) {
      ++a.gross_errors;
    }
    if (!inside(t, envelope)) continue;
    ++a.measurable;
    if (!std::isfinite(e.d_m)) continue;
    ++a.measurable_estimated;
    d_rel.push_back((e.d_m - t.d_net_m) / t.d_net_m);
    if (std::isfinite(e.psi_rad)) psi_deg.push_back(rad_to_deg(e.psi_rad - t.psi_net_rad));
    if (std::isfinite(e.pitch_rad)) {
      pitch_deg.push_back(rad_to_deg(e.pitch_rad - t.pitch_net_rad));
    }
  }
  a.d_net_rel = error_stats(d_rel);
  a.psi_net_deg = error_stats(psi_deg);
  a.pitch_net_deg = error_stats(pitch_deg);
  return a;
}

std::string describe(const NetPoseAccuracy& a) {
  char buf[512];
  std::snprintf(
      buf, sizeof(buf),
      "  frames scored %zu, measurable %zu, with an estimate %zu\n"
      "  d_net     rel. error: median %.2f%%, p95 %.2f%%, max %.2f%%\n"
      "  psi_net   error:      median %.2f deg, p95 %.2f deg, max %.2f deg\n"
      "  pitch_net error:      median %.2f deg, p95 %.2f deg, max %.2f deg\n"
      "  frames reporting a distance > %.0f%% off (of all): %zu (%.1f%%)\n",
      a.frames, a.measurable, a.measurable_estimated, 100 * a.d_net_rel.median,
      100 * a.d_net_rel.p95, 100 * a.d_net_rel.max, a.psi_net_deg.median, a.psi_net_deg.p95,
      a.psi_net_deg.max, a.pitch_net_deg.median, a.pitch_net_deg.p95, a.pitch_net_deg.max,
      100 * a.gross_rel, a.gross_errors,
      a.frames ? 100.0 * static_cast<double>(a.gross_errors) / static_cast<double>(a.frames) : 0.0);
  return buf;
}

double rho_drift_per_m(std::span<const double> t_s, std::span<const double> arc_error_m,
                       double path_m, double window_s) {
  if (t_s.empty() || t_s.size() != arc_error_m.size() || !(path_m > 0)) return kNaN;
  double sum = 0;
  int n = 0;
  for (size_t i = 0; i < t_s.size(); ++i) {
    if (t_s[i] >= t_s.back() - window_s) {
      sum += arc_error_m[i];
      ++n;
    }
  }
  return std::abs(sum / n) / path_m;
}

GlobalPoseAccuracy score_global_pose(const Dataset& dataset, std::span<const EstimateRow> rows) {
  const auto truth = truth_by_time(dataset);
  GlobalPoseAccuracy a;
  std::vector<double> r_err, z_err, rho_err, psi_err, t_s, arc_m;
  const GroundTruthRow* prev_truth = nullptr;
  const EstimateRow* ref = nullptr;
  const GroundTruthRow* ref_truth = nullptr;
  for (const EstimateRow& r : rows) {
    const auto it = truth.find(r.timestamp_ns);
    if (it == truth.end()) continue;
    const GroundTruthRow& t = *it->second;
    const Eigen::Vector3d& p = t.p_pen_body_m;
    ++a.frames;
    if (ref && prev_truth) a.path_m += (p.head<2>() - prev_truth->p_pen_body_m.head<2>()).norm();
    if (ref) prev_truth = &t;
    if (std::isfinite(r.r_g_m)) {
      ++a.with_r_g;
      r_err.push_back(r.r_g_m - std::hypot(p.x(), p.y()));
    }
    if (std::isfinite(r.z_g_m)) {
      ++a.with_z_g;
      z_err.push_back(r.z_g_m - p.z());
    }
    if (!std::isfinite(r.rho_g_rad) || !std::isfinite(r.psi_g_rad)) continue;
    ++a.with_rho_psi;
    if (!ref) {
      ref = &r;
      ref_truth = &t;
      a.reference_timestamp_ns = r.timestamp_ns;
      prev_truth = &t;
    }
    const Eigen::Vector3d& p0 = ref_truth->p_pen_body_m;
    const double rho_true = wrap_angle(std::atan2(p.y(), p.x()) - std::atan2(p0.y(), p0.x()));
    const double psi_true = wrap_angle(t.yaw_rad - ref_truth->yaw_rad);
    const double rho_err_rad = wrap_angle(wrap_angle(r.rho_g_rad - ref->rho_g_rad) - rho_true);
    rho_err.push_back(rad_to_deg(rho_err_rad));
    t_s.push_back(seconds_between(ref->timestamp_ns, r.timestamp_ns));
    arc_m.push_back(rho_err_rad * std::hypot(p.x(), p.y()));
    psi_err.push_back(rad_to_deg(wrap_angle(wrap_angle(r.psi_g_rad - ref->psi_g_rad) - psi_true)));
  }
  a.r_g_m = error_stats(r_err);
  a.z_g_m = error_stats(z_err);
  a.rho_change_deg = error_stats(rho_err);
  a.psi_change_deg = error_stats(psi_err);
  a.rho_drift_per_m = rho_drift_per_m(t_s, arc_m, a.path_m);
  return a;
}

std::string describe(const GlobalPoseAccuracy& a) {
  char buf[800];
  std::snprintf(buf, sizeof(buf),
                "  frames scored %zu: with r_g %zu, with z_g %zu, with rho_g and psi_g %zu\n"
                "  r_g error:          median %.1f mm, p95 %.1f mm, max %.1f mm\n"
                "  z_g error:          median %.1f mm, p95 %.1f mm, max %.1f mm\n"
                "  rho_g change error: median %.3f deg, p95 %.3f deg, max %.3f deg\n"
                "  psi_g change error: median %.2f deg, p95 %.2f deg, max %.2f deg\n"
                "  rho_g drift: %.3f%% of the %.2f m travelled (arc error over the last 5 s)\n",
                a.frames, a.with_r_g, a.with_z_g, a.with_rho_psi, 1e3 * a.r_g_m.median,
                1e3 * a.r_g_m.p95, 1e3 * a.r_g_m.max, 1e3 * a.z_g_m.median, 1e3 * a.z_g_m.p95,
                1e3 * a.z_g_m.max, a.rho_change_deg.median, a.rho_change_deg.p95,
                a.rho_change_deg.max, a.psi_change_deg.median, a.psi_change_deg.p95,
                a.psi_change_deg.max, 100 * a.rho_drift_per_m, a.path_m);
  return buf;
}

}  // namespace pensight
