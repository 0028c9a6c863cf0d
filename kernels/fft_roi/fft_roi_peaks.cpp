// Spectrum analysis of one ROI. shaders/fft_roi/peaks.comp mirrors this step by step (same band,
// same tie-break, same sub-harmonic and sub-bin rules) so the backends agree bin for bin.
#include <algorithm>
#include <array>
#include <cmath>
#include <utility>

#include "core/units.h"
#include "kernels/fft_roi/fft_roi.h"
#include "runtime/simd_clones.h"

namespace pensight::kernels {
namespace {

constexpr int kTop = 16;

struct Bin {
  int kx = 0, ky = 0;
  float power = -1;
};

class Spectrum {
 public:
  Spectrum(std::span<const std::complex<float>> s, int n) : s_(s), n_(n), w_(n / 2 + 1) {}

  // Power at any (kx, ky), negative kx through Hermitian symmetry.
  float power(int kx, int ky) const {
    if (kx < 0) kx = -kx, ky = -ky;
    const int row = ((ky % n_) + n_) % n_;
    const std::complex<float> c = s_[static_cast<size_t>(row) * w_ + kx];
    return c.real() * c.real() + c.imag() * c.imag();
  }
  const std::complex<float>* row(int ky) const {
    return s_.data() + static_cast<size_t>(((ky % n_) + n_) % n_) * w_;
  }
  int n() const { return n_; }
  int w() const { return w_; }

 private:
  std::span<const std::complex<float>> s_;
  int n_, w_;
};

struct Band {
  float r2_min, r2_max;
};

// In-band kx range [lo, hi] of a row of the half plane (kx > 0, or kx == 0 and ky > 0); lo > hi
// when the row has none. The same bins, in the same order, as the shader's per-bin test: the
// square roots only give the starting guesses, the float tests decide.
std::pair<int, int> band_row(const Band& band, int ky, int w) {
  const int ky2 = ky * ky;
  auto r2 = [ky2](int kx) { return static_cast<float>(kx * kx + ky2); };
  const int first = ky > 0 ? 0 : 1;
  int lo = std::max(first, static_cast<int>(std::sqrt(std::max(0.0f, band.r2_min - r2(0)))));
  while (lo > first && r2(lo - 1) >= band.r2_min) --lo;
  while (lo < w && r2(lo) < band.r2_min) ++lo;
  int hi = std::min(w - 1, static_cast<int>(std::sqrt(std::max(0.0f, band.r2_max - r2(0)))));
  while (hi + 1 < w && r2(hi + 1) <= band.r2_max) ++hi;
  while (hi >= lo && r2(hi) > band.r2_max) --hi;
  return {lo, std::max(hi, lo - 1)};
}

float power_of(std::complex<float> c) {
  return c.real() * c.real() + c.imag() * c.imag();
}

// Calls f(kx, ky, power) for every in-band bin, rows in storage order, kx ascending.
template <class F>
void for_each_in_band(const Spectrum& s, const Band& band, F f) {
  const int n = s.n();
  for (int r = 0; r < n; ++r) {
    const int ky = r < n / 2 ? r : r - n;
    const auto [lo, hi] = band_row(band, ky, s.w());
    const std::complex<float>* row = s.row(ky);
    for (int kx = lo; kx <= hi; ++kx) f(kx, ky, power_of(row[kx]));
  }
}

// Adds the powers of c[0 .. len) to 8 float lanes (vectorisable) and returns their maximum.
PENSIGHT_SIMD_CLONES float add_powers(const std::complex<float>* c, int len, float (&lanes)[8]) {
  const float* x = reinterpret_cast<const float*>(c);
  float top[8] = {};
  int i = 0;
  for (; i + 8 <= len; i += 8) {
    for (int j = 0; j < 8; ++j) {
      const float p = x[2 * (i + j)] * x[2 * (i + j)] + x[2 * (i + j) + 1] * x[2 * (i + j) + 1];
      lanes[j] += p;
      top[j] = std::max(top[j], p);
    }
  }
  for (; i < len; ++i) {
    const float p = power_of(c[i]);
    lanes[i & 7] += p;
    top[0] = std::max(top[0], p);
  }
  return *std::max_element(top, top + 8);
}

// The strongest bin kRidgeOffset0/1 bins (along b's larger axis) further out and nearer in on the
// line through DC and b, not nearer DC than kMinCoarseCycles there. Integer arithmetic on
// magnitudes, so that every backend samples the same bins.
float radial_floor(const Spectrum& s, const Bin& b) {
  const int ax = std::abs(b.kx), ay = std::abs(b.ky), r = std::max(ax, ay);
  const int sx = b.kx < 0 ? -1 : 1, sy = b.ky < 0 ? -1 : 1;
  float floor = 0;
  for (int offset : {kRidgeOffset0, kRidgeOffset1}) {
    for (int m : {r - offset, r + offset}) {
      if (m < kMinCoarseCycles) continue;
      const int x = (2 * ax * m + r) / (2 * r), y = (2 * ay * m + r) / (2 * r);
      floor = std::max(floor, s.power(sx * x, sy * y));
    }
  }
  return floor;
}

// If the spectrum at half the peak's frequency holds a peak of its own (a local maximum at least
// as strong as its radial floor) and is strong, the peak was a harmonic. A rope or seam
// along the twines is a ridge through DC in the same direction, strong at half the frequency but
// no peak there, and the lattice stays where it is (read as its half, a 1 m net gave 0.46 m).
Bin fundamental(const Spectrum& s, const Band& band, Bin p, float ratio) {
  const int hx = static_cast<int>(std::floor(static_cast<float>(p.kx) * 0.5f + 0.5f));
  const int hy = static_cast<int>(std::floor(static_cast<float>(p.ky) * 0.5f + 0.5f));
  if (static_cast<float>(hx * hx + hy * hy) < band.r2_min) return p;
  Bin best;
  for (int dy = -1; dy <= 1; ++dy) {
    for (int dx = -1; dx <= 1; ++dx) {
      const float v = s.power(hx + dx, hy + dy);
      if (v > best.power) best = {hx + dx, hy + dy, v};
    }
  }
  if (!(best.power >= ratio * p.power)) return p;
  for (int dy = -1; dy <= 1; ++dy)
    for (int dx = -1; dx <= 1; ++dx)
      if (s.power(best.kx + dx, best.ky + dy) > best.power) return p;
  if (!(best.power >= kRidgeProminence * radial_floor(s, best))) return p;
  if (best.kx < 0 || (best.kx == 0 && best.ky < 0)) best.kx = -best.kx, best.ky = -best.ky;
  return best;
}

// Whether the lattice at p is the second harmonic of a coarser one below the band: the strongest
// bin h with 2 h within one bin of p per axis (the bins a fundamental at p / 2 rounds to) is a
// local maximum at least kMinCoarseCycles from DC and at least `ratio` times p's power.
bool coarser_than_band(const Spectrum& s, const Band& band, const Bin& p, float ratio) {
  Bin best;
  for (int y2 = p.ky - 1; y2 <= p.ky + 1; ++y2) {
    for (int x2 = p.kx - 1; x2 <= p.kx + 1; ++x2) {
      if (y2 % 2 != 0 || x2 % 2 != 0) continue;
      const float v = s.power(x2 / 2, y2 / 2);
      if (v > best.power) best = {x2 / 2, y2 / 2, v};
    }
  }
  const int r2 = best.kx * best.kx + best.ky * best.ky;
  if (static_cast<float>(r2) >= band.r2_min || r2 < kMinCoarseCycles * kMinCoarseCycles ||
      !(best.power >= ratio * p.power)) {
    return false;
  }
  for (int dy = -1; dy <= 1; ++dy)
    for (int dx = -1; dx <= 1; ++dx)
      if (s.power(best.kx + dx, best.ky + dy) > best.power) return false;
  return true;
}

float energy3x3(const Spectrum& s, const Bin& b) {
  float e = 0;
  for (int dy = -1; dy <= 1; ++dy)
    for (int dx = -1; dx <= 1; ++dx) e += s.power(b.kx + dx, b.ky + dy);
  return e;
}

float log_power(float p) {
  return std::log(std::max(p, 1e-30f));
}

}  // namespace

float peak_vertex(float power_minus, float power_centre, float power_plus) {
  const float lm = log_power(power_minus), l0 = log_power(power_centre), lp = log_power(power_plus);
  const float denom = lm - 2.0f * l0 + lp;
  if (!(denom < 0.0f)) return 0.0f;
  return std::clamp(0.5f * (lm - lp) / denom, -0.5f, 0.5f);
}

RoiLattice analyze_spectrum(std::span<const std::complex<float>> spectrum, const FftRoiShape& shape,
                            const PeakParams& params) {
  const int n = shape.fft_size;
  const Spectrum s(spectrum, n);
  const float r_max = params.max_nyquist_share * static_cast<float>(n / 2);
  const Band band{params.min_cycles * params.min_cycles, r_max * r_max};

  // Pass 1: in-band energy and the strongest bin (ties: the first in row-major order).
  // Energy in 8 float lanes (vectorised per row), totals in double. The kTop strongest bins are
  // kept in (power desc, visit order) order, which is the full scan's order: pass 2 usually
  // finds its answer among them. Once kTop are kept, a row whose maximum does not beat the
  // weakest kept bin cannot change them and is not scanned bin by bin.
  double energy = 0;
  int count = 0;
  float lanes[8] = {};
  std::array<Bin, kTop> top{};
  int num_top = 0;
  float beyond = 0;  // strongest bin with r_max < r <= n / 2
  const float nyquist2 = static_cast<float>((n / 2) * (n / 2));
  for (int r = 0; r < n; ++r) {
    const int ky = r < n / 2 ? r : r - n;
    const auto [lo, hi] = band_row(band, ky, s.w());
    const std::complex<float>* row = s.row(ky);
    for (int kx = lo <= hi ? hi + 1 : (ky > 0 ? 0 : 1); kx < s.w(); ++kx) {
      const auto r2 = static_cast<float>(kx * kx + ky * ky);
      if (r2 > nyquist2) break;
      if (r2 > band.r2_max) beyond = std::max(beyond, power_of(row[kx]));
    }
    if (lo > hi) continue;
    count += hi - lo + 1;
    const float row_max = add_powers(row + lo, hi - lo + 1, lanes);
    if (num_top == kTop && !(row_max > top[kTop - 1].power)) continue;
    for (int kx = lo; kx <= hi; ++kx) {
      const float v = power_of(row[kx]);
      if (num_top == kTop && !(v > top[kTop - 1].power)) continue;
      int i = num_top < kTop ? num_top++ : kTop - 1;
      for (; i > 0 && v > top[i - 1].power; --i) top[i] = top[i - 1];
      top[i] = {kx, ky, v};
    }
  }
  for (float l : lanes) energy += l;
  RoiLattice out;
  if (num_top == 0 || top[0].power <= 0) return out;
  if (beyond > params.beyond_band_ratio * top[0].power) return out;
  Bin p1 = top[0];
  p1 = fundamental(s, band, p1, params.subharmonic_ratio);
  if (coarser_than_band(s, band, p1, params.below_band_ratio)) return out;

  // Pass 2: the strongest bin at least min_angle away from p1's direction.
  const float cos_max = std::cos(static_cast<float>(deg_to_rad(params.min_angle_deg)));
  const float c2 = cos_max * cos_max;
  const float p1_r2 = static_cast<float>(p1.kx * p1.kx + p1.ky * p1.ky);
  auto in_cone = [&](int kx, int ky) {
    const float dot = static_cast<float>(kx * p1.kx + ky * p1.ky);
    return dot * dot >= c2 * static_cast<float>(kx * kx + ky * ky) * p1_r2;
  };
  // If any kept bin is outside the cone, the first such is the scan's answer: every bin not kept
  // comes after all kept ones in the scan's order.
  Bin p2;
  for (int i = 0; i < num_top && p2.power < 0; ++i) {
    if (!in_cone(top[i].kx, top[i].ky)) p2 = top[i];
  }
  if (p2.power < 0) {
    for_each_in_band(s, band, [&](int kx, int ky, float v) {
      if (!in_cone(kx, ky) && v > p2.power) p2 = {kx, ky, v};
    });
  }
  if (p2.power <= 0) return out;
  p2 = fundamental(s, band, p2, params.subharmonic_ratio);
  if (coarser_than_band(s, band, p2, params.below_band_ratio)) return out;

  auto refine = [&](const Bin& b, float& fx, float& fy) {
    float dx = 0, dy = 0;
    if (params.subbin) {
      dx = peak_vertex(s.power(b.kx - 1, b.ky), b.power, s.power(b.kx + 1, b.ky));
      dy = peak_vertex(s.power(b.kx, b.ky - 1), b.power, s.power(b.kx, b.ky + 1));
    }
    const float inv = 1.0f / static_cast<float>(shape.roi_size_px);
    fx = (static_cast<float>(b.kx) + dx) * inv;
    fy = (static_cast<float>(b.ky) + dy) * inv;
    // A peak on the kx = 0 column may refine to kx < 0: back to the half plane.
    if (fx < 0 || (fx == 0 && fy < 0)) fx = -fx, fy = -fy;
  };
  refine(p1, out.f1x, out.f1y);
  refine(p2, out.f2x, out.f2y);
  if (std::atan2(out.f1y, out.f1x) > std::atan2(out.f2y, out.f2x)) {
    std::swap(out.f1x, out.f2x);
    std::swap(out.f1y, out.f2y);
  }
  const double peak_energy = static_cast<double>(energy3x3(s, p1)) + energy3x3(s, p2);
  out.quality = static_cast<float>(std::min(1.0, peak_energy / energy));
  out.contrast = static_cast<float>(std::min(p1.power, p2.power) / (energy / count));
  return out;
}

}  // namespace pensight::kernels
