// Tables of docs/fft_detection.md from rendered planar nets with known truth, printed (not
// tested: the bounds are the accuracy tests'): `fft_tables
// ablation|tilt-fusion|chirp-row|psi-bias`. Fixed seeds, CPU path; each takes one to a few minutes
// on two cores.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "core/units.h"
#include "pipeline/fft/net_detector.h"
#include "tests/pipeline/fft_detection/chirp_errors.h"
#include "tests/pipeline/fft_detection/sweep.h"
#include "tests/support/vulkan_fixture.h"

namespace pensight {
namespace {

using testing::NetScene;
using testing::render_all;
using testing::roi_range_errors;

struct MeshCase {
  const char* label;
  MeshType type;
  double angle_deg;
};

// The ablation table of docs/fft_detection.md: each improvement over the published method switched
// on in turn, on the same rendered frames.
void ablation() {
  const PinholeCamera cam;
  const auto full = testing::sweep_scenes(32, 7, {.noise_sigma = 3});
  const auto half = testing::sweep_scenes(16, 8, {.noise_sigma = 3, .edge_m = 0.0});
  const auto full_frames = render_all(cam, full), half_frames = render_all(cam, half);
  struct Variant {
    const char* label;
    NetDetectorConfig config;
  };
  NetDetectorConfig published{
      .fft_size = 300, .window = false, .backend = Backend::kCpu, .cpu_threads = 1};
  published.points.use_centroid = false;
  published.peaks.subbin = false;
  published.peaks.subharmonic_ratio = 1e9f;
  published.points.min_quality = 0;
  published.pose.inlier_rel = 1e9;
  published.pose.max_curvature_share = 1e9;
  NetDetectorConfig window = published;
  window.window = true;
  NetDetectorConfig subbin = window;
  subbin.peaks.subbin = true;
  NetDetectorConfig resample = subbin;
  resample.fft_size = 256;
  NetDetectorConfig centroid = resample;
  centroid.points.use_centroid = true;
  NetDetectorConfig reject = centroid;
  reject.peaks.subharmonic_ratio = 0.2f;
  reject.points.min_quality = 0.03;
  reject.pose = {};
  NetDetectorConfig small = reject;
  small.fft_size = 128;
  for (const Variant& v :
       {Variant{"published (300, no window)", published}, Variant{"+ Hann window", window},
        Variant{"+ sub-bin peaks", subbin}, Variant{"+ resample 300->256", resample},
        Variant{"+ energy centroid", centroid}, Variant{"+ rejection (default)", reject},
        Variant{"default with 128", small}}) {
    NetDetector detector(cam, v.config, testing::test_device());
    const auto e = testing::run_sweep(full_frames, full, detector);
    const auto h = testing::run_sweep(half_frames, half, detector);
    testing::print_errors(v.label, e);
    int wrong = 0;
    for (double d : h.d_rel) wrong += d > 0.2;
    std::printf("%-28s half net: d_rel median %.2f%% p95 %.2f%%, >20%% off: %d/%d, NaN %d\n", "",
                100 * testing::percentile(h.d_rel, 0.5), 100 * testing::percentile(h.d_rel, 0.95),
                wrong, h.frames, h.invalid);
  }
}

// Plane slopes alone vs fused with the per-ROI tilts (docs/fft_detection.md), on 48 full-net and
// 48 half-net frames (the net ends at the optical axis), fixed seeds.
void tilt_fusion() {
  const PinholeCamera cam;
  for (double edge : {1e9, 0.0}) {
    const auto scenes = testing::sweep_scenes(48, 8, {.noise_sigma = 3, .edge_m = edge});
    const auto frames = render_all(cam, scenes);
    for (bool fuse : {false, true}) {
      NetDetectorConfig config{.backend = Backend::kCpu};
      config.pose.fuse_roi_tilt = fuse;
      NetDetector detector(cam, config, testing::test_device());
      const std::string label = std::string(edge > 1 ? "full" : "half") + (fuse ? ", fused" : "");
      const auto e = testing::run_sweep(frames, scenes, detector);
      testing::print_errors(label.c_str(), e);
      std::printf("%-28s > 20 %% off: %ld of %d\n", "",
                  std::count_if(e.d_rel.begin(), e.d_rel.end(), [](double d) { return d > 0.2; }),
                  e.frames);
    }
  }
}

// The row of ROIs through the image centre, near to far side, as measured / corrected on the
// true plane, for the table in docs/fft_detection.md ("psi bias and the chirp correction").
void chirp_row() {
  const PinholeCamera cam{.k1 = -0.04, .k2 = 0.01};
  NetDetectorConfig config{.backend = Backend::kCpu};
  config.chirp_correction = false;
  NetDetector detector(cam, config, testing::test_device());
  for (double blur : {0.3, 0.6, 1.2}) {
    for (double psi_deg : {0.0, 30.0}) {
      for (double distance : {0.7, 1.5}) {
        NetScene s{.distance_m = distance,
                   .psi_rad = deg_to_rad(psi_deg),
                   .blur_sigma_px = blur,
                   .noise_sigma = 0};
        s.twine_m = 0.2 * s.bar_length_m;
        const NetDetection d = detector.detect(testing::render_net(cam, s));
        std::printf("blur %.1f px, psi %2.0f deg, %.1f m, range error %% as measured / corrected:",
                    blur, psi_deg, distance);
        for (size_t i = 0; i < d.points.size(); ++i) {
          if (!d.points[i].valid() || std::abs(d.points[i].centre_px.y() - 269.5) > 10) continue;
          const auto [measured, corrected] = roi_range_errors(d, i, detector, cam, s);
          std::printf(" %+.2f/%+.2f", 100 * measured, 100 * corrected);
        }
        std::printf("\n");
      }
    }
  }
}

// psi's error against the opening angle (docs/fft_detection.md): per mesh and angle, 24 frames of
// the sweep; "bias" is the least-squares slope of the signed psi error on the true psi.
void psi_bias() {
  for (const MeshCase& c :
       {MeshCase{"square", MeshType::kSquare, 90}, MeshCase{"square", MeshType::kSquare, 100},
        MeshCase{"square", MeshType::kSquare, 110}, MeshCase{"diamond", MeshType::kDiamond, 70},
        MeshCase{"diamond", MeshType::kDiamond, 90}, MeshCase{"diamond", MeshType::kDiamond, 105},
        MeshCase{"diamond", MeshType::kDiamond, 115},
        MeshCase{"diamond", MeshType::kDiamond, 120}}) {
    const PinholeCamera cam{.k1 = -0.04, .k2 = 0.01};
    NetScene base{.mesh_type = c.type,
                  .opening_angle_rad = deg_to_rad(c.angle_deg),
                  .blur_sigma_px = 0.6,
                  .noise_sigma = 3};
    base.twine_m = 0.2 * base.bar_length_m;
    base.knot_m = 1.5 * base.twine_m;
    const auto scenes = testing::sweep_scenes(24, 8, base);
    NetDetector detector(cam, {.backend = Backend::kCpu}, testing::test_device());
    double sxy = 0, sxx = 0;
    std::vector<double> abs_err;
    for (const NetScene& s : scenes) {
      const NetDetection d = detector.detect(testing::render_net(cam, s));
      if (!d.pose.valid()) continue;
      const double err = rad_to_deg(d.pose.psi_net_rad - s.psi_rad);
      sxy += err * rad_to_deg(s.psi_rad);
      sxx += std::pow(rad_to_deg(s.psi_rad), 2);
      abs_err.push_back(std::abs(err));
    }
    std::printf("%-8s %5.0f deg: psi median %.2f p95 %.2f deg, bias %+.2f %%, %zu/24 valid\n",
                c.label, c.angle_deg, testing::percentile(abs_err, 0.5),
                testing::percentile(abs_err, 0.95), 100 * sxy / sxx, abs_err.size());
  }
}

}  // namespace
}  // namespace pensight

int main(int argc, char** argv) {
  const std::string table = argc == 2 ? argv[1] : "";
  if (table == "ablation") {
    pensight::ablation();
  } else if (table == "tilt-fusion") {
    pensight::tilt_fusion();
  } else if (table == "chirp-row") {
    pensight::chirp_row();
  } else if (table == "psi-bias") {
    pensight::psi_bias();
  } else {
    std::fprintf(stderr, "usage: fft_tables ablation|tilt-fusion|chirp-row|psi-bias\n");
    return 2;
  }
  return 0;
}
