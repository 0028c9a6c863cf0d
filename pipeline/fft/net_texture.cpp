#include "pipeline/fft/net_texture.h"

#include <cmath>
#include <complex>
#include <limits>
#include <numbers>

#include <Eigen/LU>

#include "core/error.h"

namespace pensight {
namespace {

// e^{-i 2 pi f (u - c)} for the patch's pixels u = first + i.
std::vector<std::complex<double>> phasors(double f_cpp, int first, int n, double centre) {
  std::vector<std::complex<double>> e(static_cast<size_t>(n));
  for (int i = 0; i < n; ++i)
    e[static_cast<size_t>(i)] =
        std::polar(1.0, -2 * std::numbers::pi * f_cpp * (first + i - centre));
  return e;
}

// The patch's Fourier coefficient at f (cycles per pixel), phase taken at the patch centre.
std::complex<double> coefficient(const TexturePatch& p, const Eigen::Vector2d& f_cpp) {
  const auto ex = phasors(f_cpp.x(), p.first_px.x(), p.size_px, p.centre_px.x());
  const auto ey = phasors(f_cpp.y(), p.first_px.y(), p.size_px, p.centre_px.y());
  std::complex<double> sum = 0;
  for (int y = 0; y < p.size_px; ++y) {
    const float* row = p.pixels.data() + static_cast<size_t>(y) * p.size_px;
    std::complex<double> r = 0;
    for (int x = 0; x < p.size_px; ++x)
      r += static_cast<double>(row[x]) * ex[static_cast<size_t>(x)];
    sum += r * ey[static_cast<size_t>(y)];
  }
  return sum;
}

}  // namespace

TexturePatch texture_patch(const ImageU8& image, const PinholeCamera& camera, int64_t t_ns,
                           const NetTextureParams& params) {
  TexturePatch p;
  p.t_ns = t_ns;
  p.centre_px = Eigen::Vector2d(camera.cx_px, camera.cy_px);
  const int n = params.window_px;
  const int first_x = static_cast<int>(std::lround(p.centre_px.x() - 0.5 * (n - 1)));
  const int first_y = static_cast<int>(std::lround(p.centre_px.y() - 0.5 * (n - 1)));
  if (n < 8 || first_x < 0 || first_y < 0 || first_x + n > image.width ||
      first_y + n > image.height)
    return p;
  // A Hann window symmetric about the (sub-pixel) centre: its coefficient's phase is the
  // lattice's phase there.
  std::vector<double> wx(static_cast<size_t>(n)), wy(static_cast<size_t>(n));
  for (int i = 0; i < n; ++i) {
    const double sx = std::cos(std::numbers::pi * (first_x + i - p.centre_px.x()) / n);
    const double sy = std::cos(std::numbers::pi * (first_y + i - p.centre_px.y()) / n);
    wx[static_cast<size_t>(i)] = sx * sx;
    wy[static_cast<size_t>(i)] = sy * sy;
  }
  double weight = 0, weighted = 0;
  for (int y = 0; y < n; ++y)
    for (int x = 0; x < n; ++x) {
      const double w = wx[static_cast<size_t>(x)] * wy[static_cast<size_t>(y)];
      weight += w;
      weighted += w * image.at(first_x + x, first_y + y);
    }
  const double mean = weighted / weight;
  p.pixels.resize(static_cast<size_t>(n) * n);
  double sq = 0;
  for (int y = 0; y < n; ++y)
    for (int x = 0; x < n; ++x) {
      const double w = wx[static_cast<size_t>(x)] * wy[static_cast<size_t>(y)];
      const double v = w * (image.at(first_x + x, first_y + y) - mean);
      p.pixels[static_cast<size_t>(y) * n + x] = static_cast<float>(v);
      sq += v * v;
    }
  p.rms = std::sqrt(sq / (static_cast<double>(n) * n));
  p.first_px = Eigen::Vector2i(first_x, first_y);
  p.size_px = n;
  return p;
}

TextureStep texture_step(const TexturePatch& from, const TexturePatch& to,
                         const std::vector<RoiNetPoint>& points, const FftRelativePose& pose,
                         const PinholeCamera& camera, double bar_length_m,
                         const NetTextureParams& params) {
  if (!(bar_length_m > 0)) {
    throw Error("texture_step: net mesh size must be > 0 m, got " + std::to_string(bar_length_m) +
                "; set net_mesh_size_m in scene.yaml");
  }
  TextureStep s;
  s.from_ns = from.t_ns;
  if (!from.valid() || !to.valid() || from.size_px != to.size_px || !pose.valid() ||
      from.centre_px != to.centre_px || !(from.rms > 0) || !(to.rms > 0))
    return s;
  const RoiNetPoint* nearest = nullptr;
  double best = params.max_roi_offset_share * to.size_px;
  for (const RoiNetPoint& p : points) {
    const double offset = (p.centre_px - to.centre_px).norm();
    if (p.valid() && offset <= best) {
      best = offset;
      nearest = &p;
    }
  }
  if (nearest == nullptr) return s;
  Eigen::Matrix2d lattice;
  lattice << nearest->lattice1_px, nearest->lattice2_px;
  if (!(std::abs(lattice.determinant()) > 1e-6)) return s;
  const Eigen::Matrix2d reciprocal = lattice.inverse();  // rows: the duals of the image bars
  const Eigen::Vector3d normal_C =
      net_plane_normal(std::tan(pose.psi_net_rad), std::tan(pose.pitch_net_rad));
  const std::array<Eigen::Vector3d, 2> bars =
      bars_on_plane(*nearest, camera, Eigen::Vector3d(0, 0, pose.d_net_m), normal_C);
  const double n2 = static_cast<double>(to.size_px) * to.size_px;
  for (size_t i = 0; i < 2; ++i) {
    const Eigen::Vector2d f = reciprocal.row(static_cast<int>(i)).transpose();
    const std::complex<double> a = coefficient(from, f), b = coefficient(to, f);
    if (std::abs(a) < params.min_coherence * from.rms * n2 ||
        std::abs(b) < params.min_coherence * to.rms * n2 || !(bars[i].norm() > 0))
      return s;
    s.moved_bars[i] = std::arg(b * std::conj(a)) / (2 * std::numbers::pi);
    if (s.moved_bars[i] >= 0.5) s.moved_bars[i] -= 1.0;
    s.bars_C[i] = bars[i].normalized() * bar_length_m;
  }
  s.ray_C = camera.ray(to.centre_px);
  s.valid = true;
  return s;
}

}  // namespace pensight
