#include "tests/support/net_image.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <numbers>
#include <optional>
#include <random>

namespace pensight::testing {

ImageU8 render_net(const PinholeCamera& camera, const NetScene& s) {
  const double a = std::tan(s.psi_rad), b = std::tan(s.pitch_rad), c = s.distance_m;
  const Eigen::Vector3d m = Eigen::Vector3d(-a, -b, 1).normalized();
  const Eigen::Vector3d u1 = Eigen::Vector3d(m.z(), 0, -m.x()).normalized();
  const Eigen::Vector3d u2 = m.cross(u1);  // the net's down
  const double cr = std::cos(s.twine_rotation_rad), sr = std::sin(s.twine_rotation_rad);
  const Eigen::Vector3d right = cr * u1 + sr * u2, up = sr * u1 - cr * u2;
  const double theta = s.opening_angle_rad;
  const Eigen::Vector3d bar1 = s.mesh_type == MeshType::kDiamond
                                   ? std::sin(theta / 2) * right + std::cos(theta / 2) * up
                                   : right;
  const Eigen::Vector3d bar2 = s.mesh_type == MeshType::kDiamond
                                   ? -std::sin(theta / 2) * right + std::cos(theta / 2) * up
                                   : std::cos(theta) * right + std::sin(theta) * up;
  // Lattice coordinates: p = (p . e1) bar1 + (p . e2) bar2 for p in the plane (dual vectors);
  // twines lie along integer values of each.
  Eigen::Matrix<double, 3, 2> bars;
  bars << bar1 * s.bar_length_m, bar2 * s.bar_length_m;
  const Eigen::Matrix<double, 3, 2> dual = bars * (bars.transpose() * bars).inverse();
  const Eigen::Vector3d e1 = dual.col(0), e2 = dual.col(1);
  const Eigen::Vector3d lattice_shift = s.shift_right_m * u1 - s.shift_up_m * u2;
  std::mt19937_64 rng(s.seed);
  std::uniform_real_distribution<double> phase(0, 1);
  const double ph1 = phase(rng), ph2 = phase(rng);
  // Both families are e.norm() lines per metre apart, the same for a rhombus.
  const double duty = s.twine_m * e1.norm(), knot_duty = s.knot_m * e1.norm();
  std::normal_distribution<double> noise(0, s.noise_sigma);

  // Net point seen through a pixel position; nullopt where the ray misses the net.
  auto hit = [&](const Eigen::Vector2d& px) -> std::optional<Eigen::Vector3d> {
    const Eigen::Vector3d r = camera.ray(px);
    const double denom = 1 - a * r.x() - b * r.y();
    if (!(denom > 0)) return std::nullopt;
    const Eigen::Vector3d p = r * (c / denom);
    if ((p - Eigen::Vector3d(0, 0, c)).dot(u1) > s.edge_m) return std::nullopt;
    return p;
  };
  // Twine share of a stripe pattern of period 1 (twine on [0, duty)) at t, seen through a
  // Gaussian of sigma (mesh units): its Fourier series with each harmonic attenuated
  // (cos(k x) by rotation, sin(pi k duty) from a table).
  auto amplitudes = [](double d) {
    std::vector<double> amp;
    for (int k = 1; k <= 256; ++k) {
      amp.push_back(2 / (std::numbers::pi * k) * std::sin(std::numbers::pi * k * d));
    }
    return amp;
  };
  const std::vector<double> twine_amplitude = amplitudes(duty),
                            knot_amplitude = amplitudes(knot_duty);
  auto stripe = [&](double t, double sigma, double d, const std::vector<double>& amplitude) {
    const double x = 2 * std::numbers::pi * (t - 0.5 * d), c1 = std::cos(x), s1 = std::sin(x);
    const double decay = -2 * std::numbers::pi * std::numbers::pi * sigma * sigma;
    double v = d, cs = c1, sn = s1;
    for (int k = 1; k <= 256; ++k) {
      const double att = std::exp(decay * k * k);
      if (att < 1e-4) break;
      v += amplitude[k - 1] * att * cs;
      const double next = cs * c1 - sn * s1;
      sn = sn * c1 + cs * s1;
      cs = next;
    }
    return std::clamp(v, 0.0, 1.0);
  };
  // Lens PSF and the pixel's box (variance 1/12 px^2) as one Gaussian.
  const double sigma_px = std::sqrt(s.blur_sigma_px * s.blur_sigma_px + 1.0 / 12);

  const int w = camera.width_px, h = camera.height_px;
  std::vector<std::optional<Eigen::Vector3d>> hits(static_cast<size_t>(w) * h);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) hits[static_cast<size_t>(y) * w + x] = hit(Eigen::Vector2d(x, y));
  auto at = [&](int x, int y) -> const std::optional<Eigen::Vector3d>& {
    return hits[static_cast<size_t>(std::clamp(y, 0, h - 1)) * w + std::clamp(x, 0, w - 1)];
  };

  ImageU8 img(w, h);
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) {
      const auto& p = at(x, y);
      const auto &px0 = at(x - 1, y), &px1 = at(x + 1, y), &py0 = at(x, y - 1), &py1 = at(x, y + 1);
      double v = s.water_level;
      if (p && px0 && px1 && py0 && py1) {
        // Plane coordinates change by grad q per pixel; the PSF's sigma along q is |grad q|.
        const Eigen::Vector3d dx = (*px1 - *px0) / (x > 0 && x < w - 1 ? 2.0 : 1.0);
        const Eigen::Vector3d dy = (*py1 - *py0) / (y > 0 && y < h - 1 ? 2.0 : 1.0);
        const double s1 = sigma_px * std::hypot(dx.dot(e1), dy.dot(e1));
        const double s2 = sigma_px * std::hypot(dx.dot(e2), dy.dot(e2));
        const double q1 = (*p - lattice_shift).dot(e1) + ph1,
                     q2 = (*p - lattice_shift).dot(e2) + ph2;
        const double c1 = stripe(q1, s1, duty, twine_amplitude);
        const double c2 = stripe(q2, s2, duty, twine_amplitude);
        double twine = c1 + c2 - c1 * c2;
        if (knot_duty > 0) {
          // Centred on the crossings: shifted by half the difference of the two duties.
          const double shift = 0.5 * (knot_duty - duty);
          twine = std::max(twine, stripe(q1 + shift, s1, knot_duty, knot_amplitude) *
                                      stripe(q2 + shift, s2, knot_duty, knot_amplitude));
        }
        const double contrast = s.attenuation_m > 0 ? std::exp(-p->norm() / s.attenuation_m) : 1;
        v += twine * contrast * (s.net_level - s.water_level);
      }
      img.at(x, y) = static_cast<uint8_t>(std::clamp(std::lround(v + noise(rng)), 0L, 255L));
    }
  }
  return img;
}

ImageU8 render_noise(int width, int height, int lo, int hi, uint64_t seed) {
  ImageU8 img(width, height);
  std::mt19937_64 rng(seed);
  std::uniform_int_distribution<int> u(lo, hi);
  for (auto& p : img.pixels) p = static_cast<uint8_t>(u(rng));
  return img;
}

}  // namespace pensight::testing
