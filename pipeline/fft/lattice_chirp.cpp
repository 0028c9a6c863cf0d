#include "pipeline/fft/lattice_chirp.h"

#include <Eigen/LU>
#include <array>
#include <cmath>
#include <numbers>
#include <optional>

#include "pipeline/fft/net_geometry.h"

namespace pensight {

namespace {

constexpr int kPositions = 16;  // model positions per ROI axis: 19 px apart in a 300 px ROI
constexpr int kNodes = 9;       // field evaluations per ROI axis, interpolated between
constexpr int kLobe = 3;        // bins beyond the positions' lattices: the Hann main lobe and one
constexpr int kMaxSide = 128;   // bins per axis of a model spectrum; wider: no correction

// |W(u0 + b)|^2 for b = 0 .. count - 1, times `scale`: the ROI window's transform at u bins
// from a line's frequency, 1 at u = 0; sinc for no window, sinc(u) / (1 - u^2) for Hann (1/2 at
// |u| = 1). sin^2(pi u) is the same for every b, so one sine serves the row.
void window_response_row(double u0, bool hann, double scale, double* out, int count) {
  const double s = std::sin(std::numbers::pi * u0), s2 = s * s;
  for (int b = 0; b < count; ++b) {
    const double u = u0 + b, pu = std::numbers::pi * u;
    double r = std::abs(pu) < 1e-6 ? 1.0 : s2 / (pu * pu);
    if (hann) {
      const double d = 1 - u * u;
      r = std::abs(d) < 1e-6 ? 0.25 : r / (d * d);
    }
    out[b] = scale * r;
  }
}

// Amplitude response at f cycles per image pixel of what lies between the net and the spectrum:
// the sensor's pixel footprint (sinc f) and, where the ROI is resampled, the kernel's [1 2 1]
// prefilter (cos^2 pi f) and linear interpolation (sinc^2 f). Its slope pulls a chirped peak
// towards the coarser side; a lens blur adds to it, unknown here.
double transfer(double f, bool resampled) {
  const double pf = std::numbers::pi * f;
  const double sinc = std::abs(pf) < 1e-9 ? 1.0 : std::sin(pf) / pf;
  return resampled ? sinc * sinc * sinc * std::pow(std::cos(pf), 2) : sinc;
}

// The frequency field of the net lattice over the image: the lattice vectors `a` (columns, px)
// seen at pixel `c`, carried along the plane through ray(c) with normal n.
class LatticeField {
 public:
  LatticeField(const PinholeCamera& camera, const Eigen::Vector2d& c, const Eigen::Matrix2d& a,
               const Eigen::Vector3d& n)
      : camera_(camera), n_(n), p0_(camera.ray(c)) {
    RoiNetPoint seen;
    seen.centre_px = c;
    seen.lattice1_px = a.col(0);
    seen.lattice2_px = a.col(1);
    bars_ = bars_on_plane(seen, camera, p0_, n);
    ok_ = bars_[0].allFinite() && bars_[1].allFinite();
  }
  bool ok() const { return ok_; }

  // Reciprocal lattice (columns: cycles per pixel) at pixel x; nullopt where it does not project.
  std::optional<Eigen::Matrix2d> frequencies(const Eigen::Vector2d& x) const {
    const Eigen::Vector3d p = ray_on_plane(camera_.ray(x), p0_, n_);
    if (!(p.allFinite() && p.z() > 0)) return std::nullopt;
    Eigen::Matrix2d a;
    for (int i = 0; i < 2; ++i) {
      const Eigen::Vector3d h = 0.5 * bars_[static_cast<size_t>(i)];
      const auto lo = camera_.project(p - h), hi = camera_.project(p + h);
      if (!lo || !hi) return std::nullopt;
      a.col(i) = *hi - *lo;
    }
    if (!(std::abs(a.determinant()) > 1e-9)) return std::nullopt;
    return Eigen::Matrix2d(a.inverse().transpose());
  }

 private:
  const PinholeCamera& camera_;
  Eigen::Vector3d n_, p0_;
  std::array<Eigen::Vector3d, 2> bars_{};
  bool ok_ = false;
};

}  // namespace

kernels::RoiLattice chirp_corrected(const kernels::RoiLattice& measured, kernels::RoiOrigin origin,
                                    int roi_size_px, const Eigen::Vector2d& point_px,
                                    const PinholeCamera& camera, const Eigen::Vector3d& normal_C,
                                    const ChirpModelParams& params) {
  Eigen::Matrix2d f;
  f << measured.f1x, measured.f2x, measured.f1y, measured.f2y;
  if (!(std::abs(f.determinant()) > 1e-12) || !(roi_size_px > 0)) return measured;
  const LatticeField field(camera, point_px, f.inverse().transpose(), normal_C);
  const auto at_point = field.frequencies(point_px);
  if (!field.ok() || !at_point) return measured;

  // The field and the transfer^2 of both peaks at 9 x 9 nodes over the positions (each ray and
  // projection is ~0.1 us; the field is smooth, bilinear between nodes is within 0.1 % of it
  // at 30 deg): per node f1x, f1y, f2x, f2y, h1^2, h2^2.
  const double n = roi_size_px, step = n / kPositions;
  constexpr double kNodeStep = (kPositions - 1.0) / (kNodes - 1);  // positions per node step
  std::array<Eigen::Matrix<double, 6, 1>, kNodes * kNodes> node;
  for (int b = 0; b < kNodes; ++b) {
    for (int a = 0; a < kNodes; ++a) {
      const auto fq = field.frequencies({origin.x + (0.5 + a * kNodeStep) * step - 0.5,
                                         origin.y + (0.5 + b * kNodeStep) * step - 0.5});
      if (!fq) return measured;
      Eigen::Matrix<double, 6, 1>& v = node[static_cast<size_t>(b * kNodes + a)];
      for (int k = 0; k < 2; ++k) {
        const Eigen::Vector2d fk = fq->col(k);
        v.segment<2>(2 * k) = fk;
        v(4 + k) =
            std::pow(transfer(fk.x(), params.resampled) * transfer(fk.y(), params.resampled), 2);
      }
    }
  }
  // Each position's lattice (in bins) and spectral weight, window^2 times transfer^2.
  static const std::array<double, kPositions> hann2 = [] {
    std::array<double, kPositions> h{};
    for (int i = 0; i < kPositions; ++i)
      h[static_cast<size_t>(i)] = std::pow(std::sin(std::numbers::pi * (i + 0.5) / kPositions), 4);
    return h;
  }();
  constexpr int kCount = kPositions * kPositions;
  std::array<Eigen::Matrix<double, kCount, 2>, 2> bins;
  std::array<Eigen::Matrix<double, kCount, 1>, 2> weight;
  Eigen::Vector2d moment = Eigen::Vector2d::Zero();
  double energy = 0;
  for (int j = 0; j < kPositions; ++j) {
    const double ty = j / kNodeStep;
    const int by = std::min(static_cast<int>(ty), kNodes - 2);
    const double fy = ty - by;
    for (int i = 0; i < kPositions; ++i) {
      const double tx = i / kNodeStep;
      const int bx = std::min(static_cast<int>(tx), kNodes - 2);
      const double fx = tx - bx;
      const auto at = [&](int a, int b) { return node[static_cast<size_t>(b * kNodes + a)]; };
      const Eigen::Matrix<double, 6, 1> v =
          (1 - fy) * ((1 - fx) * at(bx, by) + fx * at(bx + 1, by)) +
          fy * ((1 - fx) * at(bx, by + 1) + fx * at(bx + 1, by + 1));
      const int q = j * kPositions + i;
      const double w =
          params.window ? hann2[static_cast<size_t>(i)] * hann2[static_cast<size_t>(j)] : 1.0;
      const Eigen::Vector2d xq(origin.x + (i + 0.5) * step - 0.5,
                               origin.y + (j + 0.5) * step - 0.5);
      for (size_t k = 0; k < 2; ++k) {
        bins[k].row(q) = n * v.segment<2>(2 * static_cast<int>(k)).transpose();
        weight[k](q) = w * v(4 + static_cast<int>(k));
        moment += weight[k](q) * xq;
        energy += weight[k](q);
      }
    }
  }

  // The model assumes net over the whole ROI. A ROI partly on water (the net's edge, a fish) puts
  // its measured energy centroid (the point's pixel) away from the model's.
  if (!((moment / energy - point_px).norm() <= params.max_centroid_gap_share * roi_size_px)) {
    return measured;
  }
  // Each peak's model spectrum over the bins its positions span, the window's main lobe beyond:
  // power(by, bx) = sum_q weight_q |W(by - bins_qy)|^2 |W(bx - bins_qx)|^2, one matrix product.
  // Located with the detector's rule; the measurement moves by the difference between the lattice
  // at the point and that prediction.
  kernels::RoiLattice out = measured;
  std::array<float*, 2> fx_out{&out.f1x, &out.f2x}, fy_out{&out.f1y, &out.f2y};
  for (size_t k = 0; k < 2; ++k) {
    Eigen::Vector2i lo, side;
    for (int a = 0; a < 2; ++a) {
      lo(a) = static_cast<int>(std::floor(bins[k].col(a).minCoeff())) - kLobe;
      side(a) = static_cast<int>(std::ceil(bins[k].col(a).maxCoeff())) + kLobe - lo(a) + 1;
    }
    if (side.maxCoeff() > kMaxSide) return measured;
    Eigen::MatrixXd wx(side.x(), kCount), wy(side.y(), kCount);  // a column per position
    for (int q = 0; q < kCount; ++q) {
      window_response_row(lo.x() - bins[k](q, 0), params.window, weight[k](q), &wx(0, q), side.x());
      window_response_row(lo.y() - bins[k](q, 1), params.window, 1.0, &wy(0, q), side.y());
    }
    const Eigen::MatrixXd power = wy * wx.transpose();  // rows: y bins, columns: x bins
    Eigen::Index by = 0, bx = 0;
    power.maxCoeff(&by, &bx);
    if (bx == 0 || by == 0 || bx == side.x() - 1 || by == side.y() - 1) return measured;
    const auto p = [&](Eigen::Index y, Eigen::Index x) { return static_cast<float>(power(y, x)); };
    Eigen::Vector2d predicted(lo.x() + static_cast<double>(bx), lo.y() + static_cast<double>(by));
    if (params.subbin) {
      predicted.x() += kernels::peak_vertex(p(by, bx - 1), p(by, bx), p(by, bx + 1));
      predicted.y() += kernels::peak_vertex(p(by - 1, bx), p(by, bx), p(by + 1, bx));
    }
    const Eigen::Vector2d shift = at_point->col(static_cast<int>(k)) - predicted / n;
    *fx_out[k] += static_cast<float>(shift.x());
    *fy_out[k] += static_cast<float>(shift.y());
  }
  return out;
}

}  // namespace pensight
