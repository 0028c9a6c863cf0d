// Net texture odometry (net_texture.h) through the whole detector: two analytic frames of a
// planar net whose lattice moved by a known amount within its plane.
#include "pipeline/fft/net_texture.h"

#include <gtest/gtest.h>

#include <Eigen/QR>
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <random>

#include "core/error.h"
#include "core/units.h"
#include "pipeline/dataset/dataset_reader.h"
#include "pipeline/fft/net_detector.h"
#include "tests/support/net_image.h"
#include "tests/support/test_seed.h"
#include "tests/support/vulkan_fixture.h"
#include "tools/runner.h"

namespace pensight {
namespace {

// The lattice moved by `shift_C` (in the net plane, C): the optical axis' net point moved by
// -shift_C over the net. Returns how far, in bars, each measured move is from that.
Eigen::Vector2d bars_off(const TextureStep& s, const Eigen::Vector3d& shift_C) {
  Eigen::Matrix<double, 3, 2> bars;
  bars << s.bars_C[0], s.bars_C[1];
  const Eigen::Vector2d expected = bars.colPivHouseholderQr().solve(-shift_C);
  Eigen::Vector2d off;
  for (int i = 0; i < 2; ++i) {
    const double d = s.moved_bars[static_cast<size_t>(i)] - expected(i);
    off(i) = d - std::round(d);
  }
  return off;
}

// Random nets 0.5-2 m away, 0-25 deg oblique, square or diamond meshes at 70-110 deg, moved by
// up to 0.45 bar in any direction within their plane, 2 grey levels of noise. Over 300 trials
// (PENSIGHT_TEST_SEED=1..300) the error was median 0.002 bar, p99 0.009, worst 0.012 bar; the
// bound is 0.03 bar (0.9 mm at a 30 mm bar).
TEST(NetTexture, MovedBarsAreTheLatticesMove) {
  std::mt19937_64 rng(testing::fresh_seed());
  std::uniform_real_distribution<double> u01(0, 1);
  const PinholeCamera cam;
  for (int trial = 0; trial < 6; ++trial) {
    testing::NetScene scene;
    scene.distance_m = 0.5 + 1.5 * u01(rng);
    scene.psi_rad = (u01(rng) - 0.5) * 0.87;
    scene.pitch_rad = (u01(rng) - 0.5) * 0.3;
    scene.mesh_type = trial % 2 ? MeshType::kDiamond : MeshType::kSquare;
    scene.opening_angle_rad = deg_to_rad(70 + 40 * u01(rng));
    scene.twine_m = 0.002 + 0.002 * u01(rng);
    scene.seed = rng();
    NetDetector detector(cam, {.backend = Backend::kCpu, .cpu_threads = 2}, testing::test_device());
    const NetDetection first = detector.detect(testing::render_net(cam, scene), 0);
    EXPECT_FALSE(first.texture.valid) << "the first frame has nothing to compare with";
    // Up to 0.45 bar along each of the net's right and up.
    scene.shift_right_m = (u01(rng) - 0.5) * 0.9 * scene.bar_length_m;
    scene.shift_up_m = (u01(rng) - 0.5) * 0.9 * scene.bar_length_m;
    // The seed sets the lattice's phase too, so it stays; the second frame gets its own noise.
    ImageU8 moved = testing::render_net(cam, scene);
    std::normal_distribution<double> noise(0, 2);
    for (uint8_t& v : moved.pixels)
      v = static_cast<uint8_t>(std::clamp(std::lround(v + noise(rng)), 0L, 255L));
    const NetDetection second = detector.detect(moved, 100'000'000);
    ASSERT_TRUE(second.texture.valid) << "trial " << trial;
    EXPECT_EQ(second.texture.from_ns, 0);
    // The net's right and down in C, as net_image.cpp defines them.
    const double a = std::tan(scene.psi_rad), b = std::tan(scene.pitch_rad);
    const Eigen::Vector3d m = Eigen::Vector3d(-a, -b, 1).normalized();
    const Eigen::Vector3d right = Eigen::Vector3d(m.z(), 0, -m.x()).normalized();
    const Eigen::Vector3d down = m.cross(right);
    const Eigen::Vector3d shift = scene.shift_right_m * right - scene.shift_up_m * down;
    const Eigen::Vector2d off = bars_off(second.texture, shift);
    std::printf("trial %d: %.2f m, psi %.1f deg, %s: off by %.4f / %.4f bar\n", trial,
                scene.distance_m, rad_to_deg(scene.psi_rad),
                scene.mesh_type == MeshType::kDiamond ? "diamond" : "square", off(0), off(1));
    EXPECT_LE(off.cwiseAbs().maxCoeff(), 0.03) << "trial " << trial;
    for (const Eigen::Vector3d& bar : second.texture.bars_C) {
      EXPECT_NEAR(bar.norm(), scene.bar_length_m, 1e-12);
      EXPECT_NEAR(bar.dot(m), 0.0, 0.05 * scene.bar_length_m) << "a bar leaves the net plane";
    }
  }
}

// The real frame of a full-scale pen (../shared/real/solaqua_close: sheared, fouled, soft square
// mesh) and the same frame moved by whole pixels: the step is the move of the image lattice of the
// ROI nearest the centre, f . shift in its duals' cycles. Measured: 0.004-0.007 bar for these
// shifts.
TEST(NetTexture, RealFrameMovedByWholePixels) {
  const std::filesystem::path dir =
      std::filesystem::path(PENSIGHT_SHARED_DIR) / "real" / "solaqua_close";
  ASSERT_TRUE(std::filesystem::exists(dir / "scene.yaml"))
      << dir << " is missing: the project expects ../shared/ beside its checkout";
  const Dataset d = read_dataset(dir);
  const ImageU8 image = d.load_frame(0);
  for (const Eigen::Vector2i& shift : {Eigen::Vector2i(7, -4), Eigen::Vector2i(-3, 11)}) {
    NetDetector detector(d.cam0.camera, detector_config(d.scene, {.backend = Backend::kCpu}),
                         testing::test_device());
    detector.detect(image, 0);
    ImageU8 moved(image.width, image.height);
    for (int y = 0; y < image.height; ++y)
      for (int x = 0; x < image.width; ++x)
        moved.at(x, y) = image.at(std::clamp(x - shift.x(), 0, image.width - 1),
                                  std::clamp(y - shift.y(), 0, image.height - 1));
    const NetDetection det = detector.detect(moved, 1);
    ASSERT_TRUE(det.texture.valid) << "shift " << shift.transpose();
    const Eigen::Vector2d centre(d.cam0.camera.cx_px, d.cam0.camera.cy_px);
    const RoiNetPoint* nearest = nullptr;
    for (const RoiNetPoint& p : det.points)
      if (p.valid() &&
          (!nearest || (p.centre_px - centre).norm() < (nearest->centre_px - centre).norm()))
        nearest = &p;
    ASSERT_NE(nearest, nullptr);
    Eigen::Matrix2d lattice;
    lattice << nearest->lattice1_px, nearest->lattice2_px;
    const Eigen::Vector2d expected = -lattice.inverse() * shift.cast<double>();
    for (int i = 0; i < 2; ++i) {
      const double off = det.texture.moved_bars[static_cast<size_t>(i)] - expected(i);
      std::printf("shift (%d, %d) px, bar %d: moved %.4f, expected %.4f (mod 1)\n", shift.x(),
                  shift.y(), i, det.texture.moved_bars[static_cast<size_t>(i)], expected(i));
      EXPECT_NEAR(off - std::round(off), 0.0, 0.03) << "shift " << shift.transpose();
    }
  }
}

TEST(NetTexture, NoStepWithoutANet) {
  const PinholeCamera cam;
  NetDetector detector(cam, {.backend = Backend::kCpu, .cpu_threads = 2}, testing::test_device());
  detector.detect(testing::render_noise(cam.width_px, cam.height_px, 40, 200, 1), 0);
  const NetDetection d =
      detector.detect(testing::render_noise(cam.width_px, cam.height_px, 40, 200, 2), 1);
  EXPECT_FALSE(d.texture.valid);
}

TEST(NetTexture, RejectsABarLengthThatIsNotPositive) {
  EXPECT_THROW(texture_step({}, {}, {}, {}, PinholeCamera{}, 0.0, {}), Error);
}

}  // namespace
}  // namespace pensight
