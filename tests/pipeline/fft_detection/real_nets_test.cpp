// The FFT stage on nets as they hang in the sea: sheared square and diamond meshes of any
// opening angle, knotted, with thick twines (tests/support/net_image.h), against their truth.
#include <gtest/gtest.h>

#include <random>

#include "core/units.h"
#include "tests/pipeline/fft_detection/sweep.h"
#include "tests/support/vulkan_fixture.h"

namespace pensight {
namespace {

using testing::NetScene;

struct MeshCase {
  const char* label;
  MeshType type;
  double angle_deg;
};

testing::SweepErrors run_mesh_sweep(const MeshCase& c, int frames, uint64_t seed,
                                    double blur_sigma_px = 0.6) {
  const PinholeCamera cam{.k1 = -0.04, .k2 = 0.01};
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> twine(0.12, 0.3), knot(1.2, 2.0);
  NetScene base{.mesh_type = c.type,
                .opening_angle_rad = deg_to_rad(c.angle_deg),
                .blur_sigma_px = blur_sigma_px,
                .noise_sigma = 3};
  base.twine_m = twine(rng) * base.bar_length_m;
  base.knot_m = knot(rng) * base.twine_m;
  const auto scenes = testing::sweep_scenes(frames, rng(), base);
  NetDetector detector(cam, {.backend = Backend::kCpu}, testing::test_device());
  std::vector<ImageU8> images;
  for (const NetScene& s : scenes) images.push_back(testing::render_net(cam, s));
  auto e = testing::run_sweep(images, scenes, detector, true);
  testing::print_errors(c.label, e);
  return e;
}

// Sheared square meshes (95-110 deg) and diamond meshes (70-120 deg), knotted, twines 12-30 % of
// the bar, 0.4-2.5 m, |psi| <= 35 deg: the acceptance bounds of the real-nets issue. psi reads
// about 1 % of itself low (docs/fft_detection.md), which puts a run's median at 0.11-0.16 deg
// typically and at most 0.39 deg over seeds 1-80 (docs/validation-log.md), within 0.5 deg.
TEST(RealNets, ShearedAndDiamondMeshesMeetBounds) {
  std::mt19937_64 rng(testing::fresh_seed());
  std::uniform_real_distribution<double> square(95, 110), diamond(70, 120);
  for (const MeshCase& c : {MeshCase{"sheared square", MeshType::kSquare, square(rng)},
                            MeshCase{"diamond", MeshType::kDiamond, diamond(rng)}}) {
    SCOPED_TRACE(std::string(c.label) + " at " + std::to_string(c.angle_deg) + " deg");
    const auto e = run_mesh_sweep(c, 16, rng());
    EXPECT_LE(e.invalid, 1);
    EXPECT_LE(testing::percentile(e.d_rel, 0.5), 0.01);
    EXPECT_LE(testing::percentile(e.d_rel, 0.95), 0.03);
    EXPECT_LE(testing::percentile(e.psi_deg, 0.5), 0.5);
    EXPECT_LE(testing::percentile(e.psi_deg, 0.95), 2.0);
    // The angle after the first frames (the filter starts from the first measurement).
    std::vector<double> settled(e.angle_deg.begin() + std::min<size_t>(3, e.angle_deg.size()),
                                e.angle_deg.end());
    EXPECT_LE(testing::percentile(settled, 1.0), 2.0);
    // Measured from the chirp-corrected lattices the angle is unbiased on oblique frames: the
    // median at most 0.084 deg over seeds 1-40 (measured before the correction: typically
    // 0.1 deg, 0.95 deg for seed 5004's diamond, whose d_net then read 1.35 % short).
    EXPECT_LE(testing::percentile(settled, 0.5), 0.2);
  }
}

// Soft images (the real frame's look): a Gaussian PSF of 1.5-2.5 px. Beyond ~1.8 m at +-35 deg
// the blur takes the 6 px lattice away: NaN with a reason (too few lattices, or the few left
// inconsistent), the rest within the bounds. Bounds: psi median 0.75 deg and 4 NaN frames of 12,
// over a measured worst of 0.53 deg and 2 (docs/validation-log.md).
TEST(RealNets, SoftImagesKeepTheBounds) {
  std::mt19937_64 rng(testing::fresh_seed());
  std::uniform_real_distribution<double> square(95, 110), blur(1.5, 2.5);
  const auto e =
      run_mesh_sweep({"soft sheared square", MeshType::kSquare, square(rng)}, 12, rng(), blur(rng));
  for (const std::string& reason : e.reasons) {
    EXPECT_FALSE(reason.empty());
  }
  EXPECT_LE(e.invalid, 4);
  EXPECT_LE(testing::percentile(e.d_rel, 0.5), 0.01);
  EXPECT_LE(testing::percentile(e.psi_deg, 0.5), 0.75);
}

// Beyond the envelope (3-8 m, or 55-80 deg oblique) on sheared and diamond meshes: NaN with a
// reason, or a distance within 20 %.
TEST(RealNets, OutsideTheEnvelopeNoWrongDistances) {
  const PinholeCamera cam;
  std::mt19937_64 rng(testing::fresh_seed());
  std::uniform_real_distribution<double> far(3.0, 8.0), oblique(55, 80), sign(-1, 1),
      square(95, 110), diamond(70, 120);
  NetDetector detector(cam, {.backend = Backend::kCpu}, testing::test_device());
  for (int i = 0; i < 12; ++i) {
    const bool is_diamond = i % 4 >= 2;
    NetScene s{.mesh_type = is_diamond ? MeshType::kDiamond : MeshType::kSquare,
               .opening_angle_rad = deg_to_rad(is_diamond ? diamond(rng) : square(rng)),
               .noise_sigma = 3,
               .seed = rng()};
    s.twine_m = 0.2 * s.bar_length_m;
    if (i % 2) {
      s.distance_m = far(rng);
    } else {
      s.psi_rad = deg_to_rad((sign(rng) < 0 ? -1 : 1) * oblique(rng));
    }
    const NetDetection d = detector.detect(testing::render_net(cam, s));
    if (!d.pose.valid()) {
      EXPECT_FALSE(d.pose.reason.empty());
      continue;
    }
    EXPECT_LE(std::abs(d.pose.d_net_m - s.distance_m), 0.2 * s.distance_m)
        << "d " << s.distance_m << " psi " << rad_to_deg(s.psi_rad) << " angle "
        << rad_to_deg(s.opening_angle_rad) << ": estimate " << d.pose.d_net_m;
  }
}

}  // namespace
}  // namespace pensight
