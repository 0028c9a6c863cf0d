#include "pipeline/global_pose/circle_fit.h"

#include "core/error.h"

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <string>
#include <vector>

namespace pensight::global_pose {
namespace {

struct Weighted {
  Eigen::Vector2d p;
  double w;
};

// Truncated squared residuals; stops once past `bound` (that hypothesis has already lost).
double msac_cost(const std::vector<Weighted>& pts, const Eigen::Vector2d& c, double radius,
                 double threshold, double bound) {
  double cost = 0;
  for (const auto& q : pts) {
    const double r = (q.p - c).norm() - radius;
    cost += q.w * std::min(r * r, threshold * threshold);
    if (cost > bound) break;
  }
  return cost;
}

// Centre of the circle of `radius` through a and b on the origin's side; nullopt if none.
std::optional<Eigen::Vector2d> two_point_centre(const Eigen::Vector2d& a, const Eigen::Vector2d& b,
                                                double radius) {
  const Eigen::Vector2d mid = 0.5 * (a + b);
  const Eigen::Vector2d ab = b - a;
  const double half = 0.5 * ab.norm();
  if (half < 1e-6 || half >= radius) return std::nullopt;
  const Eigen::Vector2d perp = Eigen::Vector2d(-ab.y(), ab.x()) / (2 * half);
  const double h = std::sqrt(radius * radius - half * half);
  const Eigen::Vector2d c1 = mid + h * perp, c2 = mid - h * perp;
  return c1.squaredNorm() < c2.squaredNorm() ? c1 : c2;
}

// Algebraic start: total-least-squares line through the points, the centre one radius behind it
// on the origin's side.
std::optional<Eigen::Vector2d> line_centre(const std::vector<Weighted>& pts, double radius) {
  double sw = 0;
  Eigen::Vector2d m = Eigen::Vector2d::Zero();
  for (const auto& q : pts) {
    m += q.w * q.p;
    sw += q.w;
  }
  m /= sw;
  Eigen::Matrix2d s = Eigen::Matrix2d::Zero();
  for (const auto& q : pts) s += q.w * (q.p - m) * (q.p - m).transpose();
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> eig(s);
  Eigen::Vector2d n = eig.eigenvectors().col(0);
  if (n.dot(m) < 0) n = -n;
  if (!n.allFinite()) return std::nullopt;
  return Eigen::Vector2d(m - radius * n);
}

}  // namespace

CircleFit fit_circle_known_radius(std::span<const Eigen::Vector2d> points,
                                  const CircleFitOptions& o, std::span<const double> weights) {
  CircleFit fit;
  const double radius = o.radius_m;
  if (!(radius > 0)) return fit;
  if (!weights.empty() && weights.size() != points.size())
    throw Error("circle fit: " + std::to_string(weights.size()) + " weights for " +
                std::to_string(points.size()) + " points; give one quality per net point, or none");
  std::vector<Weighted> pts;
  pts.reserve(points.size());
  for (size_t i = 0; i < points.size(); ++i) {
    const double w = weights.empty() ? 1.0 : weights[i];
    if (points[i].allFinite() && w > 0 && std::isfinite(w)) pts.push_back({points[i], w});
  }
  const int n = static_cast<int>(pts.size());
  if (n < std::max(3, o.min_inliers)) return fit;

  // Hypotheses: the algebraic line fit plus 2-point circles from a fixed pseudo-random sample of
  // well-separated pairs (deterministic, so a frame always gives the same answer). Sampling stops
  // once a hypothesis with both points inliers has been drawn with probability 1 - 1e-6 at the
  // best hypothesis' inlier ratio (at least 8 samples).
  Eigen::Vector2d best{kNaN, kNaN};
  double best_cost = std::numeric_limits<double>::infinity();
  int needed = o.max_hypotheses;
  auto consider = [&](const std::optional<Eigen::Vector2d>& c) {
    if (!c) return;
    const double cost = msac_cost(pts, *c, radius, o.outlier_threshold_m, best_cost);
    if (cost >= best_cost) return;
    best_cost = cost;
    best = *c;
    int inliers = 0;
    for (const auto& q : pts)
      inliers += std::abs((q.p - best).norm() - radius) < o.outlier_threshold_m ? 1 : 0;
    const double w = static_cast<double>(inliers) / n;
    needed = w >= 1.0 ? 0 : static_cast<int>(std::ceil(std::log(1e-6) / std::log(1 - w * w)));
  };
  consider(line_centre(pts, radius));
  uint32_t state = 0x9e3779b9u;
  auto next = [&] {
    state = state * 1664525u + 1013904223u;
    return static_cast<int>((state >> 8) % static_cast<uint32_t>(n));
  };
  for (int k = 0, tries = 0;
       k < std::min(o.max_hypotheses, std::max(needed, 8)) && tries < 4 * o.max_hypotheses;
       ++tries) {
    const int i = next(), j = next();
    if (i == j || (pts[i].p - pts[j].p).norm() < 0.25) continue;
    consider(two_point_centre(pts[i].p, pts[j].p, radius));
    ++k;
  }
  if (!best.allFinite()) return fit;

  // Gauss-Newton on (theta, d) about the centroid of the hypothesis' inliers.
  Eigen::Vector2d m = Eigen::Vector2d::Zero();
  double sw = 0;
  for (const auto& q : pts) {
    if (std::abs((q.p - best).norm() - radius) < o.outlier_threshold_m) {
      m += q.w * q.p;
      sw += q.w;
    }
  }
  if (sw <= 0) return fit;
  m /= sw;
  Eigen::Vector2d n0 = m - best;
  double theta = std::atan2(n0.y(), n0.x());
  double d = n0.norm() - radius;
  auto centre = [&](double th, double dd) {
    return Eigen::Vector2d(m - (radius + dd) * Eigen::Vector2d(std::cos(th), std::sin(th)));
  };
  Eigen::Matrix2d jtj;
  int used = 0;
  double wr2 = 0, r2sum = 0;
  for (int it = 0; it < o.max_iterations; ++it) {
    const Eigen::Vector2d nrm(std::cos(theta), std::sin(theta)), tan(-nrm.y(), nrm.x());
    const Eigen::Vector2d c = m - (radius + d) * nrm;
    jtj.setZero();
    Eigen::Vector2d jtr = Eigen::Vector2d::Zero();
    used = 0;
    wr2 = r2sum = 0;
    for (const auto& q : pts) {
      const Eigen::Vector2d diff = q.p - c;
      const double dist = diff.norm();
      const double r = dist - radius;
      if (std::abs(r) >= o.outlier_threshold_m || dist <= 0) continue;
      const Eigen::Vector2d u = diff / dist;
      const Eigen::Vector2d j((radius + d) * u.dot(tan), u.dot(nrm));
      const double huber = std::abs(r) <= o.huber_delta_m ? 1.0 : o.huber_delta_m / std::abs(r);
      const double w = q.w * huber;
      jtj += w * j * j.transpose();
      jtr += w * r * j;
      wr2 += w * r * r;
      r2sum += r * r;
      ++used;
    }
    if (used < std::max(3, o.min_inliers)) return fit;
    const Eigen::LDLT<Eigen::Matrix2d> ldlt(jtj);
    if (ldlt.info() != Eigen::Success || !(ldlt.vectorD().minCoeff() > 1e-12 * jtj.trace()))
      return fit;
    const Eigen::Vector2d step = -ldlt.solve(jtr);
    theta += step.x();
    d += step.y();
    fit.iterations = it + 1;
    if (std::abs(step.y()) < 1e-7 && std::abs(step.x()) * (radius + d) < 1e-7) break;
  }
  if (!std::isfinite(theta) || !std::isfinite(d) || radius + d <= 0) return fit;

  // Covariance of (theta, d) from the weighted residual scale, mapped to the centre.
  const Eigen::Matrix2d cov_td = wr2 / std::max(1, used - 2) * jtj.inverse();
  const Eigen::Vector2d nrm(std::cos(theta), std::sin(theta)), tan(-nrm.y(), nrm.x());
  Eigen::Matrix2d jc;
  jc.col(0) = -(radius + d) * tan;
  jc.col(1) = -nrm;
  fit.ok = true;
  fit.centre = centre(theta, d);
  fit.centre_covariance = jc * cov_td * jc.transpose();
  fit.residual_rms_m = std::sqrt(r2sum / used);
  fit.inliers = used;
  // Bearings from the observer: the points lie in front of it, so they do not wrap.
  double lo = std::numeric_limits<double>::infinity(), hi = -lo;
  for (const auto& q : pts) {
    if (std::abs((q.p - fit.centre).norm() - radius) >= o.outlier_threshold_m) continue;
    const double bearing = std::atan2(q.p.y(), q.p.x());
    lo = std::min(lo, bearing);
    hi = std::max(hi, bearing);
  }
  fit.inlier_bearing_spread_rad = hi - lo;
  return fit;
}

}  // namespace pensight::global_pose
