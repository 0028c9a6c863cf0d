#include "sim/render_cpu.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <thread>

#include "core/threads.h"
#include "sim/lamp_veil.h"
#include "sim/marine_snow.h"
#include "sim/net_mesh.h"
#include "sim/optics.h"
#include "sim/sim_hash.h"

namespace pensight::sim {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

// Box-filtered share of [x - h/2, x + h/2] covered by pulses [offset, offset + width) repeating
// with `period`: the exact integral of the pulse train, so the twine pattern fades to its mean
// coverage instead of aliasing once a mesh shrinks below a few pixels.
double pulse_coverage(double x, double h, double period, double width, double offset) {
  if (width <= 0) return 0;
  x -= offset;
  x -= period * std::floor(x / period);
  if (h < 1e-6 * period) return x < width ? 1 : 0;
  auto integral = [&](double y) {
    const double n = std::floor(y / period);
    return n * width + std::min(y - n * period, width);
  };
  return (integral(x + h / 2) - integral(x - h / 2)) / h;
}

std::optional<double> intersect_fish(const FishPose& f, const Eigen::Vector3d& o,
                                     const Eigen::Vector3d& d) {
  const Eigen::Vector3d q = o - f.centre_m;
  const double qa = q.dot(f.axis), da = d.dot(f.axis);
  const Eigen::Vector3d qp = q - qa * f.axis, dp = d - da * f.axis;
  const double ia = 1 / (f.half_length_m * f.half_length_m);
  const double ib = 1 / (f.half_thickness_m * f.half_thickness_m);
  const double A = dp.squaredNorm() * ib + da * da * ia;
  const double B = qp.dot(dp) * ib + qa * da * ia;
  const double C = qp.squaredNorm() * ib + qa * qa * ia - 1;
  const double disc = B * B - A * C;
  if (disc < 0) return std::nullopt;
  const double t = (-B - std::sqrt(disc)) / A;
  return t > 0 ? std::optional<double>(t) : std::nullopt;
}

class Tracer {
 public:
  Tracer(const Scenario& s, const NetGeometry& net, const NetLattice& lattice, const FrameState& f)
      : s_(s),
        net_(net),
        lattice_(lattice),
        f_(f),
        o_(f.T_pen_camera.translation()),
        R_pc_(f.T_pen_camera.linear()),
        seed_(fold_seed(s.seed)),
        range_(net_visible_range_m(s.water)) {
    c_ = s.water.attenuation_per_m;
    E0_ = s.light.ambient;
    background_ = s.water.backscatter * ambient(o_.z());
    const PinholeCamera& cam = s.camera.calibration.camera;
    dDx_ = R_pc_ * Eigen::Vector3d(1 / cam.fx_px, 0, 0);
    dDy_ = R_pc_ * Eigen::Vector3d(0, 1 / cam.fy_px, 0);
    n_ = s.camera.samples_per_axis;
  }

  double ambient(double z) const {
    return E0_ * std::exp(-s_.water.diffuse_attenuation_per_m * std::max(z, 0.0));
  }

  // `n_in` points into the surface (away from the viewer); twine is lit from most sides.
  double irradiance(const Eigen::Vector3d& p, const Eigen::Vector3d& n_in, bool twine) const {
    double e = ambient(p.z());
    for (const LampPose& l : f_.lamps) {
      const Eigen::Vector3d v = p - l.position_m;
      const double r2 = v.squaredNorm(), r = std::sqrt(r2);
      const Eigen::Vector3d vh = v / r;
      const double ca = vh.dot(l.direction);
      if (ca <= 0) continue;
      const double cosi = n_in.dot(vh);
      const double shade = twine ? 0.5 + 0.5 * std::abs(cosi) : std::max(cosi, 0.0);
      // cos^m fall-off and attenuation in one exp.
      e += l.intensity * shade * std::exp(l.exponent * std::log(ca) - c_ * r) / std::max(r2, 0.01);
    }
    return e;
  }

  // What a sample sees of the net: twine (and clump) coverage, the round knots' share of it,
  // the rope coverage over it, and the fouled-patch weight.
  struct NetLook {
    double cover = 0, knot = 0, rope = 0, patch = 0;
  };

  NetLook net_look(const NetHit& h, const Eigen::Vector3d& D_p, double s) const {
    const double denom = D_p.dot(h.normal);
    const Eigen::Vector3d px = s * (dDx_ - dDx_.dot(h.normal) / denom * D_p);
    const Eigen::Vector3d py = s * (dDy_ - dDy_.dot(h.normal) / denom * D_p);
    const NetConfig& n = s_.net;
    const bool wall = h.part == NetPart::kWall;
    // Footprint of the sample along u and v per pixel axis, then in the lattice's coordinates.
    Eigen::Vector2d fx(px.dot(h.tangent_u), px.dot(h.tangent_v));
    Eigen::Vector2d fy(py.dot(h.tangent_u), py.dot(h.tangent_v));
    const double hu = (std::abs(fx.x()) + std::abs(fy.x())) / n_;
    const double hv = (std::abs(fx.y()) + std::abs(fy.y())) / n_;
    Eigen::Vector2d x(h.u_m, h.v_m);
    if (lattice_.deformed()) {
      Eigen::Matrix2d J;
      lattice_.deform(h.u_m, h.v_m, h.part, x, J);
      fx = J * fx;
      fy = J * fy;
    }
    const Eigen::Vector2d &na = lattice_.normal_a(), &nb = lattice_.normal_b();
    const double qa = na.dot(x), qb = nb.dot(x);
    const double ha = (std::abs(na.dot(fx)) + std::abs(na.dot(fy))) / n_;
    const double hb = (std::abs(nb.dot(fx)) + std::abs(nb.dot(fy))) / n_;
    const double T = lattice_.period();
    NetLook look;
    double w = n.twine_width_m;
    if (n.fouling_coverage > 0) {
      const double t = lattice_.patch_threshold();
      look.patch =
          smoothstep(t - kPatchSoftness, t + kPatchSoftness,
                     value_noise(h.u_m, h.v_m, wall ? net_.fouling_cell_u() : n.fouling_scale_m,
                                 n.fouling_scale_m, wall ? net_.fouling_cells_around() : 0,
                                 seed_ ^ kStreamPatches));
      w = std::min(w * (1 + kFouledThickening * look.patch), std::max(w, kFouledMaxWidth * T));
    }
    const double ca = pulse_coverage(qa, ha, T, w, -w / 2);
    const double cb = pulse_coverage(qb, hb, T, w, -w / 2);
    double cover = 1 - (1 - cb) * (1 - ca);
    if (n.seam_spacing_m > 0) {
      const double ws = kSeamTwines * n.twine_width_m;
      const double period = wall ? lattice_.seam_u().period : n.seam_spacing_m;
      cover = 1 - (1 - cover) * (1 - pulse_coverage(h.u_m, hu, period, ws, -ws / 2));
    }
    const double k = n.knot_size_m;
    // Offsets from the nearest twine of each family.
    const double da = qa - T * std::round(qa / T), db = qb - T * std::round(qb / T);
    if (n.knot_shape == KnotShape::kSquare) {
      cover = std::max(cover,
                       pulse_coverage(qb, hb, T, k, -k / 2) * pulse_coverage(qa, ha, T, k, -k / 2));
    } else if (k > 0) {
      // A disc at the crossing, edge ramped over the footprint, fading to its mean area once
      // the footprint spans a good part of the cell.
      const double g = lattice_.normals_dot();
      const double d =
          std::sqrt(std::max(0.0, (da * da + db * db - 2 * g * da * db) / (1 - g * g)));
      const double f = 0.5 * (ha + hb);
      const double sharp = std::clamp((k / 2 - d) / std::max(f, 1e-12) + 0.5, 0.0, 1.0);
      const double fade = std::clamp((f - 0.25 * T) / (0.5 * T), 0.0, 1.0);
      look.knot = sharp + fade * (lattice_.round_knot_mean() - sharp);
      cover = std::max(cover, look.knot);
    }
    if (look.patch > 0) {
      // Fuzzy clumps beside the twines: high-frequency value noise, soft-thresholded.
      const Closure& cu = lattice_.clump_cells_u();
      const double cv = lattice_.clump_cell_v();
      const double noise = value_noise(h.u_m, h.v_m, wall ? cu.period : cv, cv, wall ? cu.count : 0,
                                       seed_ ^ kStreamClumps);
      const double reach =
          1 - smoothstep(w / 2, w / 2 + kClumpReach * T, std::min(std::abs(da), std::abs(db)));
      const double sharp = smoothstep(kClumpLo, kClumpHi, noise) * reach;
      const double fade = std::clamp((std::max(ha, hb) - 0.15 * T) / (0.35 * T), 0.0, 1.0);
      cover = 1 - (1 - cover) * (1 - look.patch * (sharp + fade * (lattice_.clump_mean() - sharp)));
    }
    look.cover = cover;
    if (n.ropes.spacing_m > 0) {
      const double rw = n.ropes.width_m;
      const double period_u = wall ? lattice_.rope_u().period : n.ropes.spacing_m;
      look.rope = 1 - (1 - pulse_coverage(h.u_m, hu, period_u, rw, -rw / 2)) *
                          (1 - pulse_coverage(h.v_m, hv, n.ropes.spacing_m, rw, -rw / 2));
    }
    return look;
  }

  struct Opaque {
    double t = kInf;
    double radiance = 0;
  };

  Opaque first_opaque(const Eigen::Vector3d& d) const {
    Opaque best;
    enum { kNone, kSurface, kFish, kWall } kind = kNone;
    int fish_index = -1;
    if (d.z() < 0) {
      best.t = -o_.z() / d.z();
      kind = kSurface;
    }
    for (size_t i = 0; i < f_.fish.size(); ++i) {
      const auto t = intersect_fish(f_.fish[i], o_, d);
      if (t && *t < best.t) {
        best.t = *t;
        kind = kFish;
        fish_index = static_cast<int>(i);
      }
    }
    if (const auto t = net_.intersect_wall(o_, d); t && *t < best.t) {
      best.t = *t;
      kind = kWall;
    }
    double J = 0;
    const Eigen::Vector3d p = o_ + best.t * d;
    switch (kind) {
      case kNone:
        best.radiance = background_;
        return best;
      case kSurface:
        J = s_.light.surface_brightness * E0_;
        break;
      case kFish: {
        const FishPose& fp = f_.fish[static_cast<size_t>(fish_index)];
        const Eigen::Vector3d q = p - fp.centre_m;
        const double qa = q.dot(fp.axis);
        const Eigen::Vector3d grad =
            (q - qa * fp.axis) / (fp.half_thickness_m * fp.half_thickness_m) +
            qa * fp.axis / (fp.half_length_m * fp.half_length_m);
        J = fp.albedo * irradiance(p, -grad.normalized(), false);
        break;
      }
      case kWall:
        J = s_.pen.wall_albedo * irradiance(p, Eigen::Vector3d::UnitX(), false);
        break;
    }
    const double T = std::exp(-c_ * best.t);
    best.radiance = J * T + background_ * (1 - T);
    return best;
  }

  // Veiling light of the lamps' beams along the ray up to t_end (cut at the visible range,
  // beyond which the light that comes back is below 1/2500 of its start).
  double lamp_backscatter(const Eigen::Vector3d& d, double t_end) const {
    if (!(s_.water.lamp_backscatter > 0)) return 0;
    return s_.water.lamp_backscatter * lamp_veil(o_, d, std::min(t_end, range_), f_.lamps, c_);
  }

  // Radiance along the camera ray D_c (camera frame, z = 1); also its net z-depth (0: none).
  double radiance(const Eigen::Vector3d& D_c, double& depth) const {
    const double len = D_c.norm();
    const Eigen::Vector3d D_p = R_pc_ * D_c, d = D_p / len;
    const Opaque opaque = first_opaque(d);
    const auto hit = net_.intersect(o_, d);
    depth = 0;
    if (!hit || hit->t >= opaque.t) return opaque.radiance + lamp_backscatter(d, opaque.t);
    if (hit->t <= range_) depth = hit->t / len * D_c.z();
    const NetLook look = net_look(*hit, D_p, hit->t / len);
    const double cover = look.cover;
    const NetConfig& n = s_.net;
    double albedo = n.albedo;
    if (n.fouling > 0) {
      // Around the wall the cells are stretched to a whole number (net_geometry.h).
      const bool wall = hit->part == NetPart::kWall;
      const int wrap = wall ? net_.fouling_cells_around() : 0;
      const double scale_u = wall ? net_.fouling_cell_u() : n.fouling_scale_m;
      albedo *= 1 - n.fouling * value_noise(hit->u_m, hit->v_m, scale_u, n.fouling_scale_m, wrap,
                                            seed_ ^ kStreamFouling);
    }
    // Fouled twines are brighter (hydroids, silt); round knots catch more light.
    albedo += look.patch * kFouledBrightening * (kFouledAlbedo - albedo);
    if (look.knot > 0) albedo *= 1 + kKnotGain * look.knot / cover;
    const double T = std::exp(-c_ * hit->t);
    const double E = irradiance(hit->point, hit->normal, true);
    const double twine = albedo * E * T + background_ * (1 - T);
    double L = cover * twine + (1 - cover) * opaque.radiance;
    if (look.rope > 0) {
      L = look.rope * (n.ropes.albedo * E * T + background_ * (1 - T)) + (1 - look.rope) * L;
    }
    return L + lamp_backscatter(d, hit->t);
  }

  int samples_per_axis() const { return n_; }

 private:
  const Scenario& s_;
  const NetGeometry& net_;
  const NetLattice& lattice_;
  const FrameState& f_;
  Eigen::Vector3d o_;
  Eigen::Matrix3d R_pc_;
  uint32_t seed_;
  double range_;
  double c_ = 0, E0_ = 0, background_ = 0;
  Eigen::Vector3d dDx_, dDy_;
  int n_ = 1;
};

}  // namespace

double net_visible_range_m(const WaterConfig& water) {
  return std::min(std::log(50.0) / water.attenuation_per_m, 65.0);
}

RenderedFrame render_cpu(const Scenario& s, const NetGeometry& net, const FrameState& f,
                         const RenderOptions& options) {
  const PinholeCamera& cam = s.camera.calibration.camera;
  const NetLattice lattice(s.net, net.u_around(), s.seed);
  const Tracer tracer(s, net, lattice, f);
  // With optics the sensor comes after the blur (optics.h): keep the radiance, unrounded.
  const bool optics = optics_enabled(s.camera);
  const bool keep_radiance = options.radiance_only || optics;
  RenderedFrame out;
  out.depth_m = ImageF32(cam.width_px, cam.height_px);
  if (keep_radiance) {
    out.radiance = ImageF32(cam.width_px, cam.height_px);
  } else {
    out.image = ImageU8(cam.width_px, cam.height_px);
  }
  const int n = tracer.samples_per_axis();
  const double gain = 255.0 * s.camera.exposure;
  ImageF32 snow(cam.width_px, cam.height_px);  // radiance of the marine snow, splatted spot by spot
  if (options.marine_snow) {
    for (const SnowSpot& spot : snow_spots(s, f)) {
      const double reach = kSnowCutoffSigmas * spot.sigma_px;
      const int x0 = std::max(0, static_cast<int>(std::ceil(spot.x_px - reach)));
      const int x1 = std::min(cam.width_px - 1, static_cast<int>(std::floor(spot.x_px + reach)));
      const int y0 = std::max(0, static_cast<int>(std::ceil(spot.y_px - reach)));
      const int y1 = std::min(cam.height_px - 1, static_cast<int>(std::floor(spot.y_px + reach)));
      for (int y = y0; y <= y1; ++y) {
        for (int x = x0; x <= x1; ++x) {
          snow.at(x, y) += static_cast<float>(snow_radiance(spot, x, y));
        }
      }
    }
  }
  const uint32_t frame_key = noise_frame_key(s, f.frame);
  auto render_row = [&](int y) {
    for (int x = 0; x < cam.width_px; ++x) {
      double L = 0, depth = 0, sample_depth = 0;
      for (int sy = 0; sy < n; ++sy) {
        for (int sx = 0; sx < n; ++sx) {
          L += tracer.radiance(cam.ray({x + (sx + 0.5) / n - 0.5, y + (sy + 0.5) / n - 0.5}),
                               sample_depth);
          // With odd n the middle sample is the pixel centre, whose depth the truth reports.
          if (2 * sx + 1 == n && 2 * sy + 1 == n) depth = sample_depth;
        }
      }
      L /= n * n;
      const Eigen::Vector3d D0 = cam.ray({static_cast<double>(x), static_cast<double>(y)});
      if (n % 2 == 0) tracer.radiance(D0, depth);
      out.depth_m.at(x, y) = static_cast<float>(depth);
      L += snow.at(x, y);
      L *= std::pow(1 / D0.norm(), 4 * s.camera.vignetting);
      const double grey = gain * L;
      if (keep_radiance) {
        out.radiance.at(x, y) = static_cast<float>(grey);
      } else {
        out.image.at(x, y) = sensor_value(grey, static_cast<uint32_t>(y * cam.width_px + x),
                                          frame_key, 0, s.camera, options.noise);
      }
    }
  };
  const int threads = worker_threads(0);
  {
    std::vector<std::jthread> pool;
    for (int t = 0; t < threads; ++t) {
      pool.emplace_back([&, t] {
        for (int y = t; y < cam.height_px; y += threads) render_row(y);
      });
    }
  }
  if (optics && !options.radiance_only) apply_optics(s, f, options, out);
  return out;
}

}  // namespace pensight::sim
