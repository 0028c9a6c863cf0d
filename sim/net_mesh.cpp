#include "sim/net_mesh.h"

#include <Eigen/LU>
#include <algorithm>
#include <cmath>
#include <numbers>
#include <vector>

#include "core/units.h"
#include "sim/sim_hash.h"

namespace pensight::sim {
namespace {

// cos and sin of an angle in degrees, exact at 90 (the square grid then has twine normals of
// exactly (1, 0) and (0, 1), and its coverage equals the axis-aligned one bit for bit).
Eigen::Vector2d cos_sin_deg(double deg) {
  if (deg == 90) return {0, 1};
  const double a = deg_to_rad(deg);
  return {std::cos(a), std::sin(a)};
}

Closure close_around(double period, double u_around) {
  if (period <= 0 || u_around <= 0) return {period, 0};
  const int n = static_cast<int>(std::max(1.0, std::round(u_around / period)));
  return {u_around / n, n};
}

// Draws from the distribution of value_noise (bilinear smoothstep blend of four uniform
// lattice values), for the quantile that sets the patch coverage.
std::vector<double> value_noise_samples() {
  constexpr uint32_t kSamples = 16384, kStream = 0x3c6ef372u;
  std::vector<double> out(kSamples);
  for (uint32_t i = 0; i < kSamples; ++i) {
    double c[4];
    for (uint32_t j = 0; j < 4; ++j) c[j] = unit_float(hash3(i, j, kStream));
    const double tx = unit_float(hash3(i, 4, kStream)), ty = unit_float(hash3(i, 5, kStream));
    const double sx = tx * tx * (3 - 2 * tx), sy = ty * ty * (3 - 2 * ty);
    const double a = c[0] + sx * (c[1] - c[0]), b = c[2] + sx * (c[3] - c[2]);
    out[i] = a + sy * (b - a);
  }
  std::sort(out.begin(), out.end());
  return out;
}

}  // namespace

double smoothstep(double lo, double hi, double x) {
  const double t = std::clamp((x - lo) / (hi - lo), 0.0, 1.0);
  return t * t * (3 - 2 * t);
}

double value_noise(double u, double v, double scale_u, double scale_v, int wrap_u, uint32_t seed) {
  const double x = u / scale_u, y = v / scale_v;
  const double fx = std::floor(x), fy = std::floor(y);
  auto column = [&](int32_t i) {
    if (wrap_u > 0) i = ((i % wrap_u) + wrap_u) % wrap_u;
    return static_cast<uint32_t>(i);
  };
  const auto i0 = static_cast<int32_t>(fx);
  const uint32_t ix = column(i0), ix1 = column(i0 + 1);
  const auto iy = static_cast<uint32_t>(static_cast<int32_t>(fy));
  auto lattice = [&](uint32_t i, uint32_t j) { return unit_float(hash2(i, j, seed)); };
  const double tx = x - fx, ty = y - fy;
  const double sx = tx * tx * (3 - 2 * tx), sy = ty * ty * (3 - 2 * ty);
  const double a = lattice(ix, iy) + sx * (lattice(ix1, iy) - lattice(ix, iy));
  const double b = lattice(ix, iy + 1) + sx * (lattice(ix1, iy + 1) - lattice(ix, iy + 1));
  return a + sy * (b - a);
}

double NetLattice::closing_step(const NetConfig& net) {
  if (net.mesh_type == MeshType::kSquare) return net.bar_length_m;
  return 2 * net.bar_length_m * cos_sin_deg(net.opening_angle_deg / 2).y();
}

NetLattice::NetLattice(const NetConfig& net, double u_around, uint64_t seed)
    : net_(net), u_around_(u_around) {
  const double P = net.bar_length_m;
  if (net.mesh_type == MeshType::kSquare) {
    // b2 turns from b1 towards the surface (-v): the detector's convention (mesh_angle.h).
    const Eigen::Vector2d cs = cos_sin_deg(net.opening_angle_deg);
    b1_ = {P, 0};
    b2_ = {P * cs.x(), -P * cs.y()};
  } else {
    const Eigen::Vector2d h = cos_sin_deg(net.opening_angle_deg / 2);
    b1_ = {P * h.y(), P * h.x()};
    b2_ = {-P * h.y(), P * h.x()};
  }
  auto normal = [](const Eigen::Vector2d& bar, const Eigen::Vector2d& other) {
    Eigen::Vector2d n(-bar.y(), bar.x());
    n /= bar.norm();
    return n.dot(other) < 0 ? Eigen::Vector2d(-n) : n;
  };
  n_a_ = normal(b1_, b2_);
  n_b_ = normal(b2_, b1_);
  period_ = n_a_.dot(b2_);
  e_b_ = (b1_ + b2_).normalized();
  // Angle mode at deform_scale_m, stretch mode 1.6 times longer so the two do not lock.
  k_g_ = 2 * std::numbers::pi / net.deform_scale_m;
  k_s_ = k_g_ / 1.6;
  s_ = net.stretch_variation;
  // The opening angle changes by sin(theta) (eps_pp - eps_bb) = 2 g sin(theta) c3 c4.
  g_ = deg_to_rad(net.opening_angle_variation_deg) / (2 * period_ / P);
  const uint32_t key = fold_seed(seed);
  for (uint32_t i = 0; i < 4; ++i) {
    phase_[i] = 2 * std::numbers::pi * unit_float(hash3(i, key, kStreamDeform));
  }
  fade_m_ = net.deform_scale_m;
  knot_mean_ = std::numbers::pi * net.knot_size_m * net.knot_size_m / 4 / (P * period_);
  rope_u_ = close_around(net.ropes.spacing_m, u_around);
  seam_u_ = close_around(net.seam_spacing_m, u_around);
  clump_v_ = kClumpCellMeshes * P;
  clump_u_ = close_around(clump_v_, u_around);
  if (net.fouling_coverage > 0) {
    const std::vector<double> q = value_noise_samples();
    const auto i = static_cast<size_t>((1 - net.fouling_coverage) * static_cast<double>(q.size()));
    patch_threshold_ = q[std::min(i, q.size() - 1)];
    double clump = 0;
    for (const double n : q) clump += smoothstep(kClumpLo, kClumpHi, n);
    clump /= static_cast<double>(q.size());
    // Mean reach of the clumps over the holes beside fully fouled twines (a 64 x 64 grid of the
    // offsets from the twines): the share of the cell they fill where the footprint hides them.
    const double w = std::min(net.twine_width_m * (1 + kFouledThickening),
                              std::max(net.twine_width_m, kFouledMaxWidth * period_)) /
                     2;
    double reach = 0;
    constexpr int kGrid = 64;
    for (int a = 0; a < kGrid; ++a) {
      for (int b = 0; b < kGrid; ++b) {
        const double d = period_ * std::min(std::abs((a + 0.5) / kGrid - 0.5),
                                            std::abs((b + 0.5) / kGrid - 0.5));
        if (d > w) reach += 1 - smoothstep(w, w + kClumpReach * period_, d);
      }
    }
    clump_mean_ = clump * reach / (kGrid * kGrid);
  }
}

void NetLattice::deform(double u, double v, NetPart part, Eigen::Vector2d& x,
                        Eigen::Matrix2d& J) const {
  const Eigen::Vector2d p(u, v), e_p(-e_b_.y(), e_b_.x());
  const double xi = e_b_.dot(p), eta = e_p.dot(p);
  const double a1 = k_s_ * xi + phase_[0], a2 = k_s_ * eta + phase_[1];
  const double a3 = k_g_ * xi + phase_[2], a4 = k_g_ * eta + phase_[3];
  const double c1 = std::cos(a1), s1 = std::sin(a1), c2 = std::cos(a2), s2 = std::sin(a2);
  const double c3 = std::cos(a3), s3 = std::sin(a3), c4 = std::cos(a4), s4 = std::sin(a4);
  // Stretch mode: pure dilation (plus shear); angle mode: pure deviatoric strain along the bars'
  // bisector (plus rotation). In the (bisector, perpendicular) frame:
  const Eigen::Vector2d D_local(s_ / k_s_ * s1 * c2 - g_ / k_g_ * s3 * c4,
                                s_ / k_s_ * c1 * s2 + g_ / k_g_ * c3 * s4);
  Eigen::Matrix2d G;
  G << s_ * c1 * c2 - g_ * c3 * c4, -s_ * s1 * s2 + g_ * s3 * s4, -s_ * s1 * s2 - g_ * s3 * s4,
      s_ * c1 * c2 + g_ * c3 * c4;
  Eigen::Matrix2d R;
  R.col(0) = e_b_;
  R.col(1) = e_p;
  Eigen::Vector2d D = R * D_local;
  Eigen::Matrix2d grad = R * G * R.transpose();
  if (part == NetPart::kWall && u_around_ > 0) {
    // Fade to 0 over fade_m_ before the azimuth seam, where u jumps by u_around_.
    const double uw = u - u_around_ * std::round(u / u_around_);
    const double dist = u_around_ / 2 - std::abs(uw);
    const double t = std::clamp(dist / fade_m_, 0.0, 1.0);
    const double w = t * t * (3 - 2 * t);
    const double dw_du =
        (dist > 0 && dist < fade_m_) ? -6 * t * (1 - t) / fade_m_ * (uw < 0 ? -1 : 1) : 0;
    grad = w * grad;
    grad.col(0) += D * dw_du;
    D *= w;
  }
  x = p + D;
  J = Eigen::Matrix2d::Identity() + grad;
}

LocalMesh NetLattice::local_mesh(double u, double v, NetPart part, double u_scale) const {
  LocalMesh m;
  m.type = net_.mesh_type;
  Eigen::Vector2d x;
  Eigen::Matrix2d J = Eigen::Matrix2d::Identity();
  if (deformed()) deform(u, v, part, x, J);
  // Knots where x' is a lattice point: a bar b in x' is J^-1 b in (u, v), and metres are
  // (u / u_scale, v).
  const Eigen::Matrix2d to_m = Eigen::Vector2d(1 / u_scale, 1).asDiagonal() * J.inverse();
  const Eigen::Vector2d B1 = to_m * b1_, B2 = to_m * b2_;
  m.opening_angle_rad = std::atan2(std::abs(B1.x() * B2.y() - B1.y() * B2.x()), B1.dot(B2));
  m.stretch = (B1.norm() + B2.norm()) / (2 * net_.bar_length_m) - 1;
  return m;
}

}  // namespace pensight::sim
