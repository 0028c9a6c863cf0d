#include "tests/support/net_image.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <random>

namespace pensight::testing {

ImageU8 render_net(const PinholeCamera& camera, const NetScene& s) {
  const double a = std::tan(s.psi_rad), b = std::tan(s.pitch_rad), c = s.distance_m;
  const Eigen::Vector3d m = Eigen::Vector3d(-a, -b, 1).normalized();
  const Eigen::Vector3d u1 = Eigen::Vector3d(m.z(), 0, -m.x()).normalized();
  const Eigen::Vector3d u2 = m.cross(u1);
  const double cr = std::cos(s.twine_rotation_rad), sr = std::sin(s.twine_rotation_rad);
  const Eigen::Vector3d e1 = (cr * u1 + sr * u2) / s.mesh_m;
  const Eigen::Vector3d e2 = (-sr * u1 + cr * u2) / s.mesh_m;
  std::mt19937_64 rng(s.seed);
  std::uniform_real_distribution<double> phase(0, 1);
  const double ph1 = phase(rng), ph2 = phase(rng);
  const double duty = s.twine_m / s.mesh_m;
  std::normal_distribution<double> noise(0, s.noise_sigma);

  ImageU8 img(camera.width_px, camera.height_px);
  const int ss = std::max(1, s.supersample);
  for (int y = 0; y < img.height; ++y) {
    for (int x = 0; x < img.width; ++x) {
      double sum = 0;
      for (int j = 0; j < ss; ++j) {
        for (int i = 0; i < ss; ++i) {
          const Eigen::Vector2d px(x - 0.5 + (i + 0.5) / ss, y - 0.5 + (j + 0.5) / ss);
          const Eigen::Vector3d r = camera.ray(px);
          const double denom = 1 - a * r.x() - b * r.y();
          if (!(denom > 0)) {
            sum += s.water_level;
            continue;
          }
          const Eigen::Vector3d p = r * (c / denom);
          if ((p - Eigen::Vector3d(0, 0, c)).dot(u1) > s.edge_m) {
            sum += s.water_level;
            continue;
          }
          const double q1 = p.dot(e1) + ph1, q2 = p.dot(e2) + ph2;
          const bool twine = q1 - std::floor(q1) < duty || q2 - std::floor(q2) < duty;
          const double contrast = s.attenuation_m > 0 ? std::exp(-p.norm() / s.attenuation_m) : 1;
          sum += s.water_level + (twine ? contrast * (s.net_level - s.water_level) : 0);
        }
      }
      const double v = sum / (ss * ss) + noise(rng);
      img.at(x, y) = static_cast<uint8_t>(std::clamp(std::lround(v), 0L, 255L));
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
