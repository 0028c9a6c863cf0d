#include "pipeline/fft/relative_pose_fft.h"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <optional>
#include <set>
#include <utility>
#include <vector>

#include "core/net_angles.h"
#include "core/units.h"

namespace pensight {
namespace {

struct Sample {
  Eigen::Vector3d p;
  double w;
  size_t roi;  // index into the caller's span
};

FftRelativePose invalid(size_t rois, int valid_rois, FftPoseStatus status, std::string reason) {
  return {status,           kNaN, kNaN, kNaN, valid_rois, 0, kNaN, std::vector<uint8_t>(rois, 0),
          std::move(reason)};
}

// Weighted least squares of z on the given regressors of (x, y); a regressor that is zero on every
// sample (a term left out) solves to 0.
template <int K, class Basis>
Eigen::Matrix<double, K, 1> fit(const std::vector<Sample>& s, const std::vector<int>& idx,
                                Basis basis) {
  Eigen::Matrix<double, K, K> ata = Eigen::Matrix<double, K, K>::Zero();
  Eigen::Matrix<double, K, 1> atb = Eigen::Matrix<double, K, 1>::Zero();
  for (int i : idx) {
    const Eigen::Matrix<double, K, 1> phi = basis(s[i].p);
    ata += s[i].w * phi * phi.transpose();
    atb += s[i].w * phi * s[i].p.z();
  }
  for (int k = 0; k < K; ++k)
    if (ata(k, k) == 0) ata(k, k) = 1;
  return ata.ldlt().solve(atb);
}

Eigen::Vector3d plane_basis(const Eigen::Vector3d& p) {
  return {1, p.x(), p.y()};
}
Eigen::Matrix<double, 6, 1> paraboloid_basis(const Eigen::Vector3d& p) {
  Eigen::Matrix<double, 6, 1> phi;
  phi << 1, p.x(), p.y(), p.x() * p.x(), p.x() * p.y(), p.y() * p.y();
  return phi;
}

// A quadratic term along a direction is fitted only where the samples sit in at least this many
// grid columns (x^2), rows (y^2) or both (x y): in three, x^2 interpolates the three columns'
// means exactly and follows their noise, which the paraboloid's value on the optical axis
// extrapolates (an oblique view whose net is seen in three columns read 8 % off, 4 % with a plane).
constexpr size_t kMinCurvaturePositions = 4;

// The paraboloid through the set, with the curvature terms its ROIs' spread measures and `keep`
// allows (the others zero).
Eigen::Matrix<double, 6, 1> fit_paraboloid(
    const std::vector<Sample>& s, const std::vector<int>& set, std::span<const RoiNetPoint> rois,
    const Eigen::Matrix<double, 6, 1>& keep = Eigen::Matrix<double, 6, 1>::Ones()) {
  std::set<int32_t> columns, rows;
  for (int i : set) {
    columns.insert(rois[s[i].roi].origin.x);
    rows.insert(rois[s[i].roi].origin.y);
  }
  const bool xx = columns.size() >= kMinCurvaturePositions;
  const bool yy = rows.size() >= kMinCurvaturePositions;
  Eigen::Matrix<double, 6, 1> terms;
  terms << 1, 1, 1, xx, xx && yy, yy;
  terms = terms.cwiseProduct(keep);
  // The product is evaluated here: an Eigen expression would refer to the basis's temporary.
  return fit<6>(s, set, [&](const Eigen::Vector3d& p) -> Eigen::Matrix<double, 6, 1> {
    return paraboloid_basis(p).cwiseProduct(terms);
  });
}

template <int K>
double residual(const Eigen::Matrix<double, K, 1>& c, const Eigen::Vector3d& p,
                Eigen::Matrix<double, K, 1> (*basis)(const Eigen::Vector3d&)) {
  return p.z() - c.dot(basis(p));
}

// Of a ROI's two normal candidates, the one nearer the given unit normal; nullopt for a point
// without normals (not from roi_net_point).
std::optional<Eigen::Vector3d> nearer_normal(const RoiNetPoint& roi,
                                             const Eigen::Vector3d& normal) {
  const auto& n = roi.normals_C;
  const Eigen::Vector3d& m = std::abs(n[0].dot(normal)) >= std::abs(n[1].dot(normal)) ? n[0] : n[1];
  if (!(m.z() > 0)) return std::nullopt;
  return m;
}

// Whether the ROI's own tilt (nearer_normal) is within the angle whose cosine is `min_cos` of the
// unit `normal`; a ROI without normals always is.
bool tilt_agrees(const RoiNetPoint& roi, const Eigen::Vector3d& normal, double min_cos) {
  const auto m = nearer_normal(roi, normal);
  return !m || std::abs(m->dot(normal)) >= min_cos;
}

// The samples on the plane (c, a, b): within `rel` of their depth and, with min_cos > -1, tilted
// like it (tilt_agrees).
std::vector<int> inliers(const std::vector<Sample>& s, std::span<const RoiNetPoint> rois,
                         const Eigen::Vector3d& plane, double rel, double min_cos) {
  const Eigen::Vector3d normal = net_plane_normal(plane(1), plane(2));
  std::vector<int> in;
  for (int i = 0; i < static_cast<int>(s.size()); ++i) {
    if (std::abs(residual<3>(plane, s[i].p, plane_basis)) <= rel * s[i].p.z() &&
        tilt_agrees(rois[s[i].roi], normal, min_cos)) {
      in.push_back(i);
    }
  }
  return in;
}

// Plane through the largest consistent subset: every triple proposes a plane, the one with the
// most inliers (then the smallest residual) wins; an inlier lies within `rel` of its depth and,
// with min_cos > -1, is tilted like the plane (a rope, seam or fold crossing ROIs that lie near
// the net's plane still shows another lattice orientation). 30 ROIs give 4060 triples, well
// under a ms.
std::vector<int> consensus(const std::vector<Sample>& s, std::span<const RoiNetPoint> rois,
                           double rel, double min_cos) {
  const int n = static_cast<int>(s.size());
  int best_count = 0;
  double best_cost = std::numeric_limits<double>::infinity();
  Eigen::Vector3d best_plane = Eigen::Vector3d::Zero();
  for (int i = 0; i < n; ++i) {
    for (int j = i + 1; j < n; ++j) {
      const Eigen::Vector3d u = s[j].p - s[i].p;
      for (int k = j + 1; k < n; ++k) {
        const Eigen::Vector3d normal = u.cross(s[k].p - s[i].p);
        // A plane through the triple that contains the viewing direction has no z = f(x, y).
        if (!(std::abs(normal.z()) > 1e-9 * normal.norm())) continue;
        const double a = -normal.x() / normal.z(), b = -normal.y() / normal.z();
        const double c = s[i].p.z() - a * s[i].p.x() - b * s[i].p.y();
        const Eigen::Vector3d plane_normal = net_plane_normal(a, b);
        int count = 0;
        double cost = 0;
        for (const Sample& q : s) {
          const double r = std::abs(q.p.z() - a * q.p.x() - b * q.p.y() - c);
          if (r <= rel * q.p.z() && tilt_agrees(rois[q.roi], plane_normal, min_cos)) {
            ++count, cost += r / q.p.z();
          }
        }
        if (count > best_count || (count == best_count && cost < best_cost)) {
          best_count = count;
          best_cost = cost;
          best_plane = {c, a, b};
        }
      }
    }
  }
  if (best_count == 0) return {};
  return inliers(s, rois, best_plane, rel, min_cos);
}

// Plane slopes (a, b) fused with the inliers' per-ROI slopes; see RelativePoseFftParams.
void fuse_roi_tilt(Eigen::Vector3d& plane, const std::vector<Sample>& s, const std::vector<int>& in,
                   std::span<const RoiNetPoint> rois) {
  // The plane's slope variances: residual variance per unit weight times (A^T W A)^-1.
  Eigen::Matrix3d ata = Eigen::Matrix3d::Zero();
  double wr2 = 0;
  for (int i : in) {
    const Eigen::Vector3d phi = plane_basis(s[i].p);
    ata += s[i].w * phi * phi.transpose();
    wr2 += s[i].w * std::pow(residual<3>(plane, s[i].p, plane_basis), 2);
  }
  const double dof = static_cast<double>(in.size()) - 3;
  if (dof < 1) return;
  const Eigen::Matrix3d cov = (wr2 / dof) * ata.inverse();
  // Each inlier's slopes from its normal candidate nearer the plane's normal.
  const Eigen::Vector3d normal = net_plane_normal(plane(1), plane(2));
  Eigen::Vector2d sum = Eigen::Vector2d::Zero(), sq = Eigen::Vector2d::Zero();
  double weight = 0;
  for (int i : in) {
    const auto m = nearer_normal(rois[s[i].roi], normal);
    if (!m) continue;
    const Eigen::Vector2d slope(-m->x() / m->z(), -m->y() / m->z());
    sum += s[i].w * slope;
    sq += s[i].w * slope.cwiseProduct(slope);
    weight += s[i].w;
  }
  if (!(weight > 0)) return;
  const Eigen::Vector2d mean = sum / weight;
  for (int k = 0; k < 2; ++k) {
    const double var_plane = cov(k + 1, k + 1);
    // The floor keeps identical per-ROI slopes (a synthetic corner case) from taking over.
    const double var_rois = std::max(sq(k) / weight - mean(k) * mean(k), 1e-8);
    if (!(var_plane > 0)) continue;
    plane(k + 1) = (plane(k + 1) / var_plane + mean(k) / var_rois) / (1 / var_plane + 1 / var_rois);
  }
  // The offset that best fits the points with the fused slopes.
  double offset = 0, total = 0;
  for (int i : in) {
    offset += s[i].w * (s[i].p.z() - plane(1) * s[i].p.x() - plane(2) * s[i].p.y());
    total += s[i].w;
  }
  plane(0) = offset / total;
}

// The z-depth where the ray through normalised image point (xn, yn) meets the plane (c, a, b);
// infinity where it does not (parallel, or behind the camera).
double ray_depth(const Eigen::Vector3d& plane, double xn, double yn) {
  const double den = 1 - plane(1) * xn - plane(2) * yn;
  const double z = plane(0) / den;
  return den > 0 && z > 0 ? z : std::numeric_limits<double>::infinity();
}

// The median angle between the inliers' own normals and the surface's at their points; 0 when
// none has normals.
double median_tilt_disagreement(const Eigen::Matrix<double, 6, 1>& surface,
                                const std::vector<Sample>& s, const std::vector<int>& in,
                                std::span<const RoiNetPoint> rois) {
  std::vector<double> angles;
  for (int i : in) {
    const Eigen::Vector3d normal = net_surface_normal(surface, s[i].p);
    if (const auto m = nearer_normal(rois[s[i].roi], normal)) {
      angles.push_back(std::acos(std::min(1.0, std::abs(m->dot(normal)))));
    }
  }
  if (angles.empty()) return 0;
  const auto mid = angles.begin() + static_cast<std::ptrdiff_t>(angles.size() / 2);
  std::nth_element(angles.begin(), mid, angles.end());
  return *mid;
}

// Which side of the fold line of planes a and b (where the ray meets both at the same depth) the
// normalised image point (xn, yn) lies on: the sign of depth_b - depth_a there, times c_a c_b.
double fold_side(const Eigen::Vector3d& a, const Eigen::Vector3d& b, double xn, double yn) {
  return a(0) * (1 - b(1) * xn - b(2) * yn) - b(0) * (1 - a(1) * xn - a(2) * yn);
}

// The smallest relative depth gap between a set's points and the other plane along their rays.
double closest_gap(const std::vector<Sample>& s, const std::vector<int>& set,
                   const Eigen::Vector3d& other) {
  double gap = std::numeric_limits<double>::infinity();
  for (int i : set) {
    const Eigen::Vector3d& p = s[i].p;
    gap = std::min(gap, std::abs(ray_depth(other, p.x() / p.z(), p.y() / p.z()) - p.z()) / p.z());
  }
  return gap;
}

// A point within this share of inlier_rel of the other panel's depth lies by the fold line and
// counts on neither side: a ROI straddling it reads a depth between the two panels.
constexpr double kFoldLineShare = 0.25;

// Whether the two sets lie on either side of their planes' fold line, each touching it (a point
// of each within 4 x rel of the other plane's depth: a ROI centre 0.17 of the focal length from a
// 28 deg fold at 1.5 m is 11 % off the other panel): two panels meeting. A point by the fold line
// (kFoldLineShare) may be on either side. Two planes always meet somewhere; a fish or a
// harmonic's plane does not meet the net where its ROIs are.
bool meet_in_a_fold(const std::vector<Sample>& s, const std::vector<int>& in_a,
                    const Eigen::Vector3d& a, const std::vector<int>& in_b,
                    const Eigen::Vector3d& b, double rel) {
  // Counts the set's points clearly on the positive and negative side of the fold line.
  const auto sides = [&](const std::vector<int>& set, const Eigen::Vector3d& other) {
    std::pair<int, int> n{0, 0};
    for (int i : set) {
      const Eigen::Vector3d& p = s[i].p;
      const double xn = p.x() / p.z(), yn = p.y() / p.z();
      if (std::abs(ray_depth(other, xn, yn) - p.z()) <= kFoldLineShare * rel * p.z()) continue;
      (fold_side(a, b, xn, yn) > 0 ? n.first : n.second) += 1;
    }
    return n;
  };
  const auto [a_pos, a_neg] = sides(in_a, b);
  const auto [b_pos, b_neg] = sides(in_b, a);
  // Each set on its side, but for one in eight of its clear points (a ROI across the fold whose
  // lattice mixes both panels' reads a range between them).
  const auto on_side = [](int here, int there) { return here > 0 && 8 * there <= here + there; };
  const bool separated = (on_side(a_pos, a_neg) && on_side(b_neg, b_pos)) ||
                         (on_side(a_neg, a_pos) && on_side(b_pos, b_neg));
  return separated && closest_gap(s, in_a, b) <= 4 * rel && closest_gap(s, in_b, a) <= 4 * rel;
}

struct Fold {
  Eigen::Vector3d plane;  // the second plane
  std::vector<int> in;    // its inliers (indices into the samples)
};

// The consensus among a subset of the samples (consensus()), as indices into all of them.
std::vector<int> consensus_among(const std::vector<Sample>& s, const std::vector<int>& subset,
                                 std::span<const RoiNetPoint> rois, double rel, double min_cos) {
  std::vector<Sample> sub;
  for (int i : subset) sub.push_back(s[static_cast<size_t>(i)]);
  std::vector<int> in = consensus(sub, rois, rel, min_cos);
  for (int& i : in) i = subset[static_cast<size_t>(i)];
  return in;
}

// The samples split in two by their own tilts (each ROI's normal candidate nearer the plane's, as
// slopes): two-means, started from the split across the slopes' principal direction. Two panels
// whose kink is under twice max_roi_tilt_rad both agree with the plane between them; their
// tilts still form two clusters. Empty sets where a sample has no normal.
std::pair<std::vector<int>, std::vector<int>> split_by_tilt(const std::vector<Sample>& s,
                                                            std::span<const RoiNetPoint> rois,
                                                            const Eigen::Vector3d& plane,
                                                            const std::vector<int>& set) {
  const Eigen::Vector3d normal = net_plane_normal(plane(1), plane(2));
  std::vector<Eigen::Vector2d> slope;
  Eigen::Vector2d mean = Eigen::Vector2d::Zero();
  for (int i : set) {
    const auto m = nearer_normal(rois[s[i].roi], normal);
    if (!m) return {};
    slope.emplace_back(-m->x() / m->z(), -m->y() / m->z());
    mean += slope.back();
  }
  if (slope.empty()) return {};
  mean /= static_cast<double>(slope.size());
  Eigen::Matrix2d scatter = Eigen::Matrix2d::Zero();
  for (const Eigen::Vector2d& v : slope) scatter += (v - mean) * (v - mean).transpose();
  const Eigen::Vector2d axis =
      Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d>(scatter).eigenvectors().col(1);
  std::vector<uint8_t> second(slope.size());
  for (size_t k = 0; k < slope.size(); ++k) second[k] = (slope[k] - mean).dot(axis) < 0;
  for (int round = 0; round < 5; ++round) {
    Eigen::Vector2d centre[2] = {Eigen::Vector2d::Zero(), Eigen::Vector2d::Zero()};
    double count[2] = {0, 0};
    for (size_t k = 0; k < slope.size(); ++k) centre[second[k]] += slope[k], ++count[second[k]];
    if (count[0] == 0 || count[1] == 0) break;
    centre[0] /= count[0];
    centre[1] /= count[1];
    for (size_t k = 0; k < slope.size(); ++k) {
      second[k] = (slope[k] - centre[1]).squaredNorm() < (slope[k] - centre[0]).squaredNorm();
    }
  }
  std::pair<std::vector<int>, std::vector<int>> sets;
  for (size_t k = 0; k < slope.size(); ++k)
    (second[k] ? sets.second : sets.first).push_back(set[k]);
  return sets;
}

// Two panels explain their ROIs at most this share of the rms residual of one smooth surface
// through them all (the paraboloid, or the plane below min_paraboloid_rois), or they are one
// surface: a pen wall's curvature turns the normal by 7-11 deg across the view at 1.5-2.5 m and
// splits into two planes as well as a fold does, but the paraboloid follows it.
constexpr double kFoldResidualShare = 0.5;

// The sum of the set's squared residuals about the plane or paraboloid c.
template <int K>
double squared_residuals(const std::vector<Sample>& s, const std::vector<int>& set,
                         const Eigen::Matrix<double, K, 1>& c,
                         Eigen::Matrix<double, K, 1> (*basis)(const Eigen::Vector3d&)) {
  double sq = 0;
  for (int i : set) sq += std::pow(residual<K>(c, s[i].p, basis), 2);
  return sq;
}

bool two_panels_fit_better(const std::vector<Sample>& s, std::span<const RoiNetPoint> rois,
                           const std::vector<int>& in_a, const Eigen::Vector3d& a,
                           const std::vector<int>& in_b, const Eigen::Vector3d& b,
                           const RelativePoseFftParams& params) {
  std::vector<int> both = in_a;
  both.insert(both.end(), in_b.begin(), in_b.end());
  const double n = static_cast<double>(both.size());
  const double two =
      squared_residuals<3>(s, in_a, a, plane_basis) + squared_residuals<3>(s, in_b, b, plane_basis);
  const double one =
      static_cast<int>(both.size()) >= params.min_paraboloid_rois
          ? squared_residuals<6>(s, both, fit_paraboloid(s, both, rois), paraboloid_basis)
          : squared_residuals<3>(s, both, fit<3>(s, both, plane_basis), plane_basis);
  return std::sqrt(two / n) <= kFoldResidualShare * std::sqrt(one / n);
}

// Two panels among all the samples, split by their tilts (split_by_tilt), each half's consensus
// plane taking the samples on it, that are a fold (is_fold).
struct TwoPanels {
  Eigen::Vector3d plane;  // the first panel's
  std::vector<int> in;    // its ROIs
  Fold fold;              // the second panel
};

// Whether planes a and b through the two sets are two panels meeting in a fold: at least
// min_fold_angle_rad apart, meeting where their ROIs are (meet_in_a_fold), and fitting them
// better than one smooth surface (two_panels_fit_better).
bool is_fold(const std::vector<Sample>& s, std::span<const RoiNetPoint> rois,
             const std::vector<int>& in_a, const Eigen::Vector3d& a, const std::vector<int>& in_b,
             const Eigen::Vector3d& b, const RelativePoseFftParams& params) {
  const double cos_angle = net_plane_normal(a(1), a(2)).dot(net_plane_normal(b(1), b(2)));
  return cos_angle <= std::cos(params.min_fold_angle_rad) &&
         meet_in_a_fold(s, in_a, a, in_b, b, params.inlier_rel) &&
         two_panels_fit_better(s, rois, in_a, a, in_b, b, params);
}

std::optional<TwoPanels> fold_within(const std::vector<Sample>& s,
                                     std::span<const RoiNetPoint> rois,
                                     const Eigen::Vector3d& plane,
                                     const RelativePoseFftParams& params, double min_cos,
                                     int need) {
  std::vector<int> all(s.size());
  for (size_t i = 0; i < all.size(); ++i) all[i] = static_cast<int>(i);
  const auto [a, b] = split_by_tilt(s, rois, plane, all);
  // Each half's own consensus plane: a fish or a harmonic among them is left out.
  const auto half_plane = [&](const std::vector<int>& half) -> std::optional<Eigen::Vector3d> {
    if (static_cast<int>(half.size()) < need) return std::nullopt;
    const std::vector<int> in = consensus_among(s, half, rois, params.inlier_rel, min_cos);
    if (static_cast<int>(in.size()) < need) return std::nullopt;
    return fit<3>(s, in, plane_basis);
  };
  const auto plane_a = half_plane(a), plane_b = half_plane(b);
  if (!plane_a || !plane_b) return std::nullopt;
  TwoPanels two{*plane_a, {}, {*plane_b, {}}};
  // Each sample to the panel it lies on and is tilted like, the nearer where both.
  const Eigen::Vector3d normal_a = net_plane_normal(two.plane(1), two.plane(2)),
                        normal_b = net_plane_normal(two.fold.plane(1), two.fold.plane(2));
  for (int i = 0; i < static_cast<int>(s.size()); ++i) {
    const double limit = params.inlier_rel * s[i].p.z();
    const double ra = std::abs(residual<3>(two.plane, s[i].p, plane_basis)),
                 rb = std::abs(residual<3>(two.fold.plane, s[i].p, plane_basis));
    const bool on_a = ra <= limit && tilt_agrees(rois[s[i].roi], normal_a, min_cos),
               on_b = rb <= limit && tilt_agrees(rois[s[i].roi], normal_b, min_cos);
    if (on_a && (!on_b || ra <= rb)) {
      two.in.push_back(i);
    } else if (on_b) {
      two.fold.in.push_back(i);
    }
  }
  if (static_cast<int>(two.in.size()) < need || static_cast<int>(two.fold.in.size()) < need) {
    return std::nullopt;
  }
  two.plane = fit<3>(s, two.in, plane_basis);
  two.fold.plane = fit<3>(s, two.fold.in, plane_basis);
  if (!is_fold(s, rois, two.in, two.plane, two.fold.in, two.fold.plane, params))
    return std::nullopt;
  return two;
}

// A second plane through the ROIs off `plane` (not in `in`), as many as a pose needs, that meets
// it in a fold (two panels, a seam; is_fold).
std::optional<Fold> find_fold(const std::vector<Sample>& s, std::span<const RoiNetPoint> rois,
                              const Eigen::Vector3d& plane, const std::vector<int>& in,
                              const RelativePoseFftParams& params, double min_cos, int need) {
  std::vector<uint8_t> taken(s.size(), 0);
  for (int i : in) taken[static_cast<size_t>(i)] = 1;
  std::vector<int> rest;
  for (int i = 0; i < static_cast<int>(s.size()); ++i) {
    if (!taken[static_cast<size_t>(i)]) rest.push_back(i);
  }
  if (static_cast<int>(rest.size()) < need) return std::nullopt;
  Fold fold;
  fold.in = consensus_among(s, rest, rois, params.inlier_rel, min_cos);
  if (static_cast<int>(fold.in.size()) < need) return std::nullopt;
  fold.plane = fit<3>(s, fold.in, plane_basis);
  if (!is_fold(s, rois, in, plane, fold.in, fold.plane, params)) return std::nullopt;
  return fold;
}

// A wall's section through the optical axis at obliquity a curves 1 / cos^3 a times as much
// as the wall; this margin over that covers the paraboloid's own error (at 6.5 m from a 12 m
// pen wall it reads 0.078-0.087 /m for 0.083).
constexpr double kWallCurvatureMargin = 1.5;

// Per term of the paraboloid (c, a, b, q1, q2, q3), 1 where it curves no more than the pen wall
// (RelativePoseFftParams::wall_curvature_per_m) seen at its obliquity, else 0 (the plane's terms
// are always 1): a fold, a bulge or a seam's kink seen as one smooth surface curves several times
// more (0.5-0.7 /m by the folds of scenarios/fold.yaml on a 12 m wall), and its normals would
// vouch for ROIs on two panels.
Eigen::Matrix<double, 6, 1> wall_like_terms(const Eigen::Matrix<double, 6, 1>& q,
                                            const RelativePoseFftParams& params) {
  const double cos_obliquity =
      std::min(std::abs(net_plane_normal(q(1), 0).z()), std::abs(net_plane_normal(0, q(2)).z()));
  const double limit = kWallCurvatureMargin * params.wall_curvature_per_m /
                       (cos_obliquity * cos_obliquity * cos_obliquity);
  Eigen::Matrix<double, 6, 1> terms;
  terms << 1, 1, 1, std::abs(2 * q(3)) <= limit, std::abs(q(4)) <= limit,
      std::abs(2 * q(5)) <= limit;
  return terms;
}

bool curved_like_the_wall(const Eigen::Matrix<double, 6, 1>& q,
                          const RelativePoseFftParams& params) {
  return wall_like_terms(q, params).minCoeff() > 0;
}

// The pen wall's curvature terms (q1, q2, q3) in a paraboloid q through the set that does not
// curve like the wall as a whole: q refitted with only its terms that do, when that still curves
// like the wall, else zeros (a bulge, a fold). Its normals, not the plane's, are the net's at the
// ROIs: rows of ROIs over a sixth of the image's height (five overlapping 533 px rows on a 720 px
// camera) take 0.1-0.16 /m of the fouling's noise into q3 at 2.5 m, and the plane's normals 5 deg
// off the wall at the sides read a diamond's opening angle 0.8 deg open, d_net 0.9 % short.
Eigen::Vector3d wall_curvature_terms(const std::vector<Sample>& s, const std::vector<int>& set,
                                     std::span<const RoiNetPoint> rois,
                                     const Eigen::Matrix<double, 6, 1>& q,
                                     const RelativePoseFftParams& params) {
  const Eigen::Matrix<double, 6, 1> keep = wall_like_terms(q, params);
  if (!(keep.tail<3>().array() * q.tail<3>().array().abs() > 0).any()) {
    return Eigen::Vector3d::Zero();
  }
  const Eigen::Matrix<double, 6, 1> refit = fit_paraboloid(s, set, rois, keep);
  return curved_like_the_wall(refit, params) ? Eigen::Vector3d(refit.tail<3>())
                                             : Eigen::Vector3d::Zero();
}

// The fused plane's checks (see RelativePoseFftParams): the extrapolation lever and the median
// disagreement of the inliers' own tilts (0 when not checked), and the reason when either is
// beyond its limit. `wall` is the paraboloid where it curves like the pen wall, else null.
struct PlaneChecks {
  FftPoseStatus status = FftPoseStatus::kValid;
  std::string reason;
  double lever = 0;
  double tilt_disagreement_rad = 0;
};

PlaneChecks check_plane(const Eigen::Vector3d& plane, const Eigen::Matrix<double, 6, 1>* wall,
                        const std::vector<Sample>& s, const std::vector<int>& in,
                        std::span<const RoiNetPoint> rois, const RelativePoseFftParams& params) {
  PlaneChecks c;
  const double gain_x = 1 + plane(1) * plane(1), gain_y = 1 + plane(2) * plane(2);  // 1/cos^2
  c.lever = std::numeric_limits<double>::infinity();
  for (int i : in) {
    const Eigen::Vector3d& p = s[i].p;
    c.lever = std::min(c.lever, (std::abs(p.x()) * gain_x + std::abs(p.y()) * gain_y) / p.z());
  }
  if (c.lever > params.max_extrapolation_lever) {
    char text[160];
    std::snprintf(text, sizeof text,
                  "net points too far from the optical axis for this obliquity (lever %.2f, "
                  "limit %.2f): d_net would be extrapolated",
                  c.lever, params.max_extrapolation_lever);
    c.status = FftPoseStatus::kExtrapolated;
    c.reason = text;
    return c;
  }
  if (!params.check_tilts) return c;
  // The tilts agree with the plane or with the pen wall through the points: a wall 6 m away turns
  // its normal by +-14 deg across a wide view, which each ROI sees and one plane does not.
  Eigen::Matrix<double, 6, 1> flat = Eigen::Matrix<double, 6, 1>::Zero();
  flat.head<3>() = plane;
  c.tilt_disagreement_rad = median_tilt_disagreement(flat, s, in, rois);
  if (wall != nullptr) {
    c.tilt_disagreement_rad =
        std::min(c.tilt_disagreement_rad, median_tilt_disagreement(*wall, s, in, rois));
  }
  if (c.tilt_disagreement_rad > params.max_tilt_disagreement_rad) {
    char text[160];
    std::snprintf(text, sizeof text,
                  "the ROIs' own tilts disagree with the fitted plane (median %.0f deg, limit "
                  "%.0f): a lattice harmonic?",
                  rad_to_deg(c.tilt_disagreement_rad),
                  rad_to_deg(params.max_tilt_disagreement_rad));
    c.status = FftPoseStatus::kTiltsDisagree;
    c.reason = text;
  }
  return c;
}

// 1 - value / limit, in [0, 1]: how far a check stayed from refusing the frame.
double margin(double value, double limit) {
  return std::clamp(1.0 - value / limit, 0.0, 1.0);
}

}  // namespace

Eigen::Vector3d net_plane_normal(double slope_x, double slope_y) {
  return Eigen::Vector3d(slope_x, slope_y, -1).normalized();
}

Eigen::Vector3d net_surface_normal(const Eigen::Matrix<double, 6, 1>& c,
                                   const Eigen::Vector3d& p_C) {
  return net_plane_normal(c(1) + 2 * c(3) * p_C.x() + c(4) * p_C.y(),
                          c(2) + c(4) * p_C.x() + 2 * c(5) * p_C.y());
}

namespace {

// The pose from the ROIs whose points and (min_cos > -1) own tilts agree with one plane.
FftRelativePose solve(std::span<const RoiNetPoint> rois, const RelativePoseFftParams& params,
                      double min_cos) {
  std::vector<Sample> s;
  for (size_t i = 0; i < rois.size(); ++i) {
    const RoiNetPoint& r = rois[i];
    if (!r.valid() || !(r.p_C.z() > 0)) continue;
    s.push_back({r.p_C, std::max(r.quality, 1e-6), i});
  }
  const int valid = static_cast<int>(s.size());
  const int need = std::max(3, params.min_valid_rois);
  if (valid < need) {
    return invalid(rois.size(), valid, FftPoseStatus::kTooFewRois,
                   "only " + std::to_string(valid) + " of " + std::to_string(rois.size()) +
                       " ROIs show a net lattice (need " + std::to_string(need) + ")");
  }
  std::vector<int> in = consensus(s, rois, params.inlier_rel, min_cos);
  if (static_cast<int>(in.size()) < need) {
    return invalid(rois.size(), valid, FftPoseStatus::kNoConsensus,
                   "no plane is consistent with " + std::to_string(need) + " of the " +
                       std::to_string(valid) + " net points");
  }
  Eigen::Vector3d plane = fit<3>(s, in, plane_basis);
  in = inliers(s, rois, plane, params.inlier_rel, min_cos);
  if (static_cast<int>(in.size()) < need) {
    return invalid(rois.size(), valid, FftPoseStatus::kRefitLost,
                   "the refitted plane keeps fewer than " + std::to_string(need) + " net points");
  }
  plane = fit<3>(s, in, plane_basis);
  // A fold: the pose is the panel's the optical axis meets, the other panel's ROIs named.
  std::vector<int> second;
  std::optional<Fold> fold;
  // Two panels whose kink is under twice max_roi_tilt_rad both agree with the plane between them
  // (fold_within); a sharper kink leaves the other panel's ROIs off this plane (find_fold).
  if (params.check_tilts) {
    if (auto two = fold_within(s, rois, plane, params, min_cos, need)) {
      plane = two->plane;
      in = std::move(two->in);
      fold = std::move(two->fold);
    }
  }
  if (!fold) fold = find_fold(s, rois, plane, in, params, min_cos, need);
  if (fold) {
    second = fold->in;
    // The optical axis on the second panel's side of the fold line: the pose is that panel's.
    const int i = fold->in.front();
    const double roi_side =
        fold_side(plane, fold->plane, s[i].p.x() / s[i].p.z(), s[i].p.y() / s[i].p.z());
    if (roi_side * fold_side(plane, fold->plane, 0, 0) > 0) {
      std::swap(second, in);
      plane = fold->plane;
    }
  }
  if (params.fuse_roi_tilt) fuse_roi_tilt(plane, s, in, rois);

  // d_net's surface: the paraboloid where enough inliers measure the wall's curvature and it
  // stays near the plane on the optical axis, else the plane.
  Eigen::Matrix<double, 6, 1> surface = Eigen::Matrix<double, 6, 1>::Zero();
  surface.head<3>() = plane;
  bool curved = false;
  if (static_cast<int>(in.size()) >= params.min_paraboloid_rois) {
    const auto q = fit_paraboloid(s, in, rois);
    if (std::abs(q(0) - plane(0)) <= params.max_curvature_share * plane(0)) {
      surface = q;
      curved = true;
    }
  }
  // The net's angles where the optical axis meets it: on a surface that curves like the pen wall,
  // its slope there along each direction it curves in; else the plane's. A plane through a curved
  // wall's points has the slope of a chord: 3 deg off at 5.6 m from a 12 m wall seen by a wide
  // camera. A paraboloid through a bulging net close up (a real one at 0.36 m) turns its slopes
  // with the bulge, 2 deg apart between the frame and its half-size copy; the plane's agree.
  const bool wall = curved && curved_like_the_wall(surface, params);
  const auto [psi, pitch] =
      net_angles_from_plane_C(wall && surface(3) != 0 ? surface(1) : plane(1),
                              wall && surface(5) != 0 ? surface(2) : plane(2));
  if (std::abs(psi) > params.max_obliquity_rad || std::abs(pitch) > params.max_obliquity_rad) {
    return invalid(rois.size(), valid, FftPoseStatus::kTooOblique,
                   "net too oblique (psi " + std::to_string(std::lround(rad_to_deg(psi))) +
                       " deg, pitch " + std::to_string(std::lround(rad_to_deg(pitch))) +
                       " deg; limit " +
                       std::to_string(std::lround(rad_to_deg(params.max_obliquity_rad))) + ")");
  }
  PlaneChecks checks = check_plane(plane, wall ? &surface : nullptr, s, in, rois, params);
  if (checks.status != FftPoseStatus::kValid) {
    return invalid(rois.size(), valid, checks.status, std::move(checks.reason));
  }
  FftRelativePose pose{FftPoseStatus::kValid,
                       surface(0),
                       psi,
                       pitch,
                       valid,
                       static_cast<int>(in.size()),
                       0,
                       std::vector<uint8_t>(rois.size(), 0),
                       {}};
  pose.surface_C << surface(0), std::tan(psi), std::tan(pitch), 0, 0, 0;
  if (wall) {
    pose.surface_C.tail<3>() = surface.tail<3>();
  } else if (curved) {
    pose.surface_C.tail<3>() = wall_curvature_terms(s, in, rois, surface, params);
  }
  for (int i : in) pose.inlier[s[i].roi] = 1;
  pose.second_panel.assign(rois.size(), 0);
  for (int i : second) pose.second_panel[s[i].roi] = 1;
  pose.other_tilt.assign(rois.size(), 0);
  for (const Sample& q : s) {
    if (!pose.inlier[q.roi] && !pose.second_panel[q.roi] &&
        std::abs(residual<3>(plane, q.p, plane_basis)) <= params.inlier_rel * q.p.z()) {
      pose.other_tilt[q.roi] = 1;
    }
  }
  const double sq = curved ? squared_residuals<6>(s, in, surface, paraboloid_basis)
                           : squared_residuals<3>(s, in, plane, plane_basis);
  pose.rms_residual_m = std::sqrt(sq / static_cast<double>(in.size()));
  const double inliers = static_cast<double>(in.size());
  pose.quality = std::min(1.0, inliers / params.full_support_rois) * (inliers / valid) *
                 margin(std::max(std::abs(psi), std::abs(pitch)), params.max_obliquity_rad) *
                 margin(checks.lever, params.max_extrapolation_lever) *
                 margin(checks.tilt_disagreement_rad, params.max_tilt_disagreement_rad) *
                 margin(pose.rms_residual_m, params.inlier_rel * pose.d_net_m);
  return pose;
}

}  // namespace

FftRelativePose relative_pose_fft(std::span<const RoiNetPoint> rois,
                                  const RelativePoseFftParams& params) {
  if (params.check_tilts) {
    FftRelativePose agreeing = solve(rois, params, std::cos(params.max_roi_tilt_rad));
    if (agreeing.valid()) return agreeing;
  }
  // Points alone: a pose where the tilts only blur the consensus, else the reason it fails.
  return solve(rois, params, -2);
}

}  // namespace pensight
