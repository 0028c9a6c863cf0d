#include "sim/marine_snow.h"

#include <algorithm>
#include <cmath>

#include "sim/sim_hash.h"

namespace pensight::sim {
namespace {

constexpr double kCell_m = 0.5;        // the water is cut into cubes of this size ...
constexpr int kCandidatesPerCell = 8;  // ... each holding up to this many particles
// The density is defined on the reference camera (720x540, fx = 462): marine_snow particles in
// view per 24x24 px cell, between kSnowNear_m and kSnowFar_m.
constexpr double kReferenceCells = 720.0 * 540.0 / (24.0 * 24.0);
constexpr double kReferenceFrustum_m3 =
    (720.0 / 462.0) * (540.0 / 462.0) *
    (kSnowFar_m * kSnowFar_m * kSnowFar_m - kSnowNear_m * kSnowNear_m * kSnowNear_m) / 3.0;
// Spots are at least this wide (anti-aliasing), keeping their energy, and at most this wide
// (the nearest particles are out of focus anyway; it bounds the Vulkan renderer's tile lists).
constexpr double kMinSigma_px = 0.7, kMaxSigma_px = 6.0;

}  // namespace

double snow_radiance(const SnowSpot& spot, double x, double y) {
  const double dx = x - spot.x_px, dy = y - spot.y_px;
  const double q = (dx * dx + dy * dy) / (spot.sigma_px * spot.sigma_px);
  if (q >= kSnowCutoffSigmas * kSnowCutoffSigmas) return 0;
  return spot.peak * std::exp(-0.5 * q);
}

std::vector<SnowSpot> snow_spots(const Scenario& s, const FrameState& f) {
  std::vector<SnowSpot> spots;
  const WaterConfig& w = s.water;
  if (!(w.marine_snow > 0)) return spots;
  const PinholeCamera& cam = s.camera.calibration.camera;
  const double density_per_m3 = w.marine_snow * kReferenceCells / kReferenceFrustum_m3;
  const double p_candidate =
      std::min(1.0, density_per_m3 * kCell_m * kCell_m * kCell_m / kCandidatesPerCell);

  // The view's bounds in normalised coordinates (corner rays, with a margin for wide spots).
  Eigen::Vector2d lo(1e9, 1e9), hi(-1e9, -1e9);
  for (const double x : {-0.5, cam.width_px - 0.5}) {
    for (const double y : {-0.5, cam.height_px - 0.5}) {
      const Eigen::Vector3d r = cam.ray({x, y});
      lo = lo.cwiseMin(r.head<2>());
      hi = hi.cwiseMax(r.head<2>());
    }
  }
  const Eigen::Vector2d margin = 0.1 * (hi - lo);
  lo -= margin;
  hi += margin;

  // Water-frame box around the view frustum between near and far.
  const Eigen::Vector3d drift = w.current_mps * f.t_s;
  Eigen::Vector3d box_lo = Eigen::Vector3d::Constant(1e9), box_hi = -box_lo;
  for (const double z : {kSnowNear_m, kSnowFar_m}) {
    for (const double x : {lo.x(), hi.x()}) {
      for (const double y : {lo.y(), hi.y()}) {
        const Eigen::Vector3d p = f.T_pen_camera * Eigen::Vector3d(x * z, y * z, z) - drift;
        box_lo = box_lo.cwiseMin(p);
        box_hi = box_hi.cwiseMax(p);
      }
    }
  }
  const Eigen::Vector3i c_lo = (box_lo / kCell_m).array().floor().cast<int>();
  const Eigen::Vector3i c_hi = (box_hi / kCell_m).array().floor().cast<int>();

  const Eigen::Isometry3d T_camera_pen = f.T_pen_camera.inverse();
  // Light scattered by a particle at p: the ambient light from above (half of it, the
  // particle's lower half is dark) and the lamps' beams, as the renderers light surfaces.
  auto light_at = [&](const Eigen::Vector3d& p) {
    double e = 0.5 * s.light.ambient * std::exp(-w.diffuse_attenuation_per_m * p.z());
    for (const LampPose& l : f.lamps) {
      const Eigen::Vector3d v = p - l.position_m;
      const double r2 = v.squaredNorm(), r = std::sqrt(r2);
      const double ca = v.dot(l.direction) / r;
      if (ca <= 0) continue;
      e += l.intensity * std::exp(l.exponent * std::log(ca) - w.attenuation_per_m * r) /
           std::max(r2, 0.01);
    }
    return e;
  };
  const uint32_t stream = fold_seed(s.seed) ^ kStreamSnow;
  for (int cz = c_lo.z(); cz <= c_hi.z(); ++cz) {
    for (int cy = c_lo.y(); cy <= c_hi.y(); ++cy) {
      for (int cx = c_lo.x(); cx <= c_hi.x(); ++cx) {
        const uint32_t cell = hash3(static_cast<uint32_t>(cx), static_cast<uint32_t>(cy),
                                    static_cast<uint32_t>(cz) ^ stream);
        for (uint32_t k = 0; k < kCandidatesPerCell; ++k) {
          uint32_t h = hash3(cell, k, stream);
          if (unit_float(h) >= p_candidate) continue;
          Eigen::Vector3d p_water;
          p_water.x() = (cx + unit_float(h = hash32(h))) * kCell_m;
          p_water.y() = (cy + unit_float(h = hash32(h))) * kCell_m;
          p_water.z() = (cz + unit_float(h = hash32(h))) * kCell_m;
          const double size = unit_float(h = hash32(h));
          const double shade = 0.4 + 0.6 * unit_float(hash32(h));
          const Eigen::Vector3d p_pen = p_water + drift;
          if (p_pen.z() < 0) continue;  // no particles above the water
          const Eigen::Vector3d p_c = T_camera_pen * p_pen;
          const double z = p_c.z();
          if (z < kSnowNear_m || z > kSnowFar_m) continue;
          const Eigen::Vector2d xn = p_c.head<2>() / z;
          if ((xn.array() < lo.array()).any() || (xn.array() > hi.array()).any()) continue;
          const auto px = cam.project(p_c);
          if (!px) continue;
          SnowSpot spot;
          spot.x_px = px->x();
          spot.y_px = px->y();
          // Gaussian radius 1.5 - 7 mm: 0.7 - 3.2 px at 1 m with fx = 462.
          const double sigma = cam.fx_px * (0.0015 + 0.0055 * size * size) / z;
          const double energy =
              sigma < kMinSigma_px ? (sigma / kMinSigma_px) * (sigma / kMinSigma_px) : 1.0;
          spot.sigma_px = std::clamp(sigma, kMinSigma_px, kMaxSigma_px);
          spot.peak = w.snow_brightness * light_at(p_pen) * shade * energy *
                      std::exp(-w.attenuation_per_m * p_c.norm());
          const double reach = kSnowCutoffSigmas * spot.sigma_px;
          if (spot.x_px < -reach || spot.y_px < -reach || spot.x_px > cam.width_px - 1 + reach ||
              spot.y_px > cam.height_px - 1 + reach) {
            continue;
          }
          spots.push_back(spot);
        }
      }
    }
  }
  return spots;
}

}  // namespace pensight::sim
