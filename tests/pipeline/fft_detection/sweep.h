#pragma once
// Rendered sweeps for the FFT detector's accuracy tests and the ablation table in
// docs/fft_detection.md: frames of a planar net at known distance / heading / pitch.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>
#include <string>
#include <vector>

#include "core/units.h"
#include "pipeline/fft/net_detector.h"
#include "tests/support/net_image.h"

namespace pensight::testing {

struct SweepErrors {
  std::vector<double> d_rel;    // |d - d_true| / d_true of frames with a valid pose
  std::vector<double> psi_deg;  // |psi - psi_true|
  std::vector<double> pitch_deg;
  std::vector<double> angle_deg;     // |opening angle - truth| of frames that report one
  std::vector<std::string> reasons;  // of the NaN frames
  int frames = 0;
  int invalid = 0;
};

inline double percentile(std::vector<double> v, double q) {
  if (v.empty()) return NAN;
  std::sort(v.begin(), v.end());
  const size_t i = static_cast<size_t>(std::lround(q * static_cast<double>(v.size() - 1)));
  return v[i];
}

// Frames drawn over 0.4-2.5 m, |psi| <= 35 deg, |pitch| <= 15 deg, any twine rotation within
// +-10 deg, with the given camera and render options.
inline std::vector<NetScene> sweep_scenes(int count, uint64_t seed, const NetScene& base = {}) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> logd(std::log(0.4), std::log(2.5)), psi(-35, 35),
      pitch(-15, 15), rot(-10, 10);
  std::vector<NetScene> scenes;
  for (int i = 0; i < count; ++i) {
    NetScene s = base;
    s.distance_m = std::exp(logd(rng));
    s.psi_rad = deg_to_rad(psi(rng));
    s.pitch_rad = deg_to_rad(pitch(rng));
    s.twine_rotation_rad = deg_to_rad(rot(rng));
    s.seed = rng();
    scenes.push_back(s);
  }
  return scenes;
}

inline SweepErrors run_sweep(const std::vector<ImageU8>& frames,
                             const std::vector<NetScene>& scenes, NetDetector& detector,
                             bool verbose = false) {
  SweepErrors e;
  for (size_t i = 0; i < frames.size(); ++i) {
    const NetScene& s = scenes[i];
    const NetDetection d = detector.detect(frames[i]);
    ++e.frames;
    if (!d.pose.valid()) {
      ++e.invalid;
      e.reasons.push_back(d.pose.reason);
      if (verbose)
        std::printf("  d %.2f psi %5.1f: NaN (%s), angle %.2f (frame %.2f)\n", s.distance_m,
                    rad_to_deg(s.psi_rad), d.pose.reason.c_str(), rad_to_deg(d.mesh_angle_rad),
                    rad_to_deg(d.mesh_angle_frame.opening_angle_rad));
      continue;
    }
    e.d_rel.push_back(std::abs(d.pose.d_net_m - s.distance_m) / s.distance_m);
    e.psi_deg.push_back(rad_to_deg(std::abs(d.pose.psi_net_rad - s.psi_rad)));
    e.pitch_deg.push_back(rad_to_deg(std::abs(d.pose.pitch_net_rad - s.pitch_rad)));
    if (!std::isnan(d.mesh_angle_rad)) {
      e.angle_deg.push_back(rad_to_deg(std::abs(d.mesh_angle_rad - s.opening_angle_rad)));
    }
    if (verbose) {
      std::printf(
          "  d %.2f psi %5.1f pitch %5.1f -> d %.3f (%+.2f%%) psi %+.2f pitch %+.2f, %d/%d, "
          "angle %.2f (frame %.2f)\n",
          s.distance_m, rad_to_deg(s.psi_rad), rad_to_deg(s.pitch_rad), d.pose.d_net_m,
          100 * (d.pose.d_net_m - s.distance_m) / s.distance_m,
          rad_to_deg(d.pose.psi_net_rad - s.psi_rad),
          rad_to_deg(d.pose.pitch_net_rad - s.pitch_rad), d.pose.inlier_rois, d.pose.valid_rois,
          rad_to_deg(d.mesh_angle_rad), rad_to_deg(d.mesh_angle_frame.opening_angle_rad));
    }
  }
  return e;
}

// The scenes rendered through `cam`, one frame each.
inline std::vector<ImageU8> render_all(const PinholeCamera& cam,
                                       const std::vector<NetScene>& scenes) {
  std::vector<ImageU8> frames;
  for (const NetScene& s : scenes) frames.push_back(render_net(cam, s));
  return frames;
}

inline void print_errors(const char* label, const SweepErrors& e) {
  std::printf(
      "%-28s d_rel median %.2f%% p95 %.2f%% | psi median %.2f p95 %.2f deg | pitch median %.2f "
      "p95 %.2f deg | angle median %.2f max %.2f deg | NaN %d/%d\n",
      label, 100 * percentile(e.d_rel, 0.5), 100 * percentile(e.d_rel, 0.95),
      percentile(e.psi_deg, 0.5), percentile(e.psi_deg, 0.95), percentile(e.pitch_deg, 0.5),
      percentile(e.pitch_deg, 0.95), percentile(e.angle_deg, 0.5), percentile(e.angle_deg, 1.0),
      e.invalid, e.frames);
}

}  // namespace pensight::testing
