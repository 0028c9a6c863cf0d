// The planned ROI side and FFT size (grid_plan.h): the reference camera keeps 300 / 256 px, other
// cameras and meshes get ROIs holding the same cells, values given stay, and the detector builds
// on every frame size from 160x120 to 3840x2160 (what a user's camera gives,
// docs/fft_detection.md).
#include "pipeline/fft/grid_plan.h"

#include <gtest/gtest.h>

#include <string>

#include "core/error.h"
#include "tests/support/error_message.h"
#include "tests/support/vulkan_fixture.h"

namespace pensight {
namespace {

struct Planned {
  int roi_px, fft;
};

Planned plan(const PinholeCamera& camera, double bar_m = 0.030, NetDetectorConfig c = {}) {
  c.bar_length_m = bar_m;
  const NetDetectorConfig p = planned_detector_config(c, camera);
  return {p.grid.roi_size_px, p.fft_size};
}

TEST(GridPlan, ROIsHoldTheReferenceCellsWithinTheFrame) {
  const auto expect = [](Planned p, int roi_px, int fft, const char* what) {
    EXPECT_EQ(p.roi_px, roi_px) << what;
    EXPECT_EQ(p.fft, fft) << what;
  };
  expect(plan(default_field_of_view(720, 540)), 300, 256, "the reference");
  expect(plan(default_field_of_view(1920, 1080)), 800, 256, "1080p, same field of view");
  expect(plan(default_field_of_view(3840, 2160)), 1600, 256, "4K");
  // Below 256 px a power of two within 25 %: the FFT reads the ROI's own pixels.
  expect(plan(default_field_of_view(320, 240)), 128, 128, "320x240 (133 px wanted)");
  expect(plan(default_field_of_view(160, 120)), 64, 64, "the smallest frame (67 px wanted)");
  expect(plan(default_field_of_view(720, 540), 0.020), 200, 128,
         "20 mm bars: no power of two near");
  expect(plan(default_field_of_view(720, 540), 0.040), 400, 256, "40 mm bars: cells 1.33x larger");
  // SOLAQUA's camera (../shared/real): 1280x720, fx 735, 27.5 mm bars.
  PinholeCamera solaqua = default_field_of_view(1280, 720);
  solaqua.fx_px = solaqua.fy_px = 735;
  expect(plan(solaqua, 0.0275), 438, 256, "solaqua");
  // A long lens on a small frame: the ROI stops at 85 % of the frame's smaller side less the
  // border, so the rows keep a baseline.
  PinholeCamera tele = default_field_of_view(640, 360);
  tele.fx_px = tele.fy_px = 1500;
  expect(plan(tele), 306, 256, "telephoto");
  NetDetectorConfig bordered;
  bordered.grid.border_px = 40;
  expect(plan(tele, 0.030, bordered), 272, 256, "telephoto, 40 px border");
  // A coarse mesh close up on a small frame: 222 px wanted, 153 px at most, 128 px taken.
  expect(plan(default_field_of_view(320, 180), 0.050), 128, 128, "320x180, 50 mm bars");
  // Values given stay; a planned ROI below 256 px gets its own power of two.
  NetDetectorConfig given;
  given.grid.roi_size_px = 200;
  expect(plan(default_field_of_view(720, 540), 0.030, given), 200, 128, "ROI given");
  given.fft_size = 64;
  expect(plan(default_field_of_view(720, 540), 0.030, given), 200, 64, "both given");
}

TEST(GridPlan, TheDetectorBuildsOnEveryFrameSizeAndRefusesTooSmallOnes) {
  NetDetectorConfig cpu;
  cpu.backend = Backend::kCpu;
  cpu.cpu_threads = 1;
  for (const auto& [w, h] : {std::pair{160, 120},
                             {320, 180},
                             {336, 189},
                             {640, 480},
                             {720, 576},
                             {1280, 720},
                             {1920, 1080},
                             {3840, 2160}}) {
    SCOPED_TRACE(std::to_string(w) + "x" + std::to_string(h));
    const NetDetector d(default_field_of_view(w, h), cpu, testing::test_device());
    EXPECT_EQ(d.rois().size(), 30u);
    EXPECT_LE(d.config().grid.roi_size_px, h);
    EXPECT_EQ(d.config().fft_size & (d.config().fft_size - 1), 0);
  }
  // An ROI given larger than the frame: the error names both sizes and the fix.
  NetDetectorConfig large = cpu;
  large.grid.roi_size_px = 300;
  const std::string e = testing::error_message(
      [&] { NetDetector(default_field_of_view(320, 240), large, testing::test_device()); });
  EXPECT_NE(e.find("ROIs of 300 px with a border of 0 px do not fit a 320x240 image"),
            std::string::npos)
      << e;
  // Below 160x120 the grid is not planned: the error names the size and the fix; with the ROI
  // side given such a frame is the user's choice.
  const std::string tiny = testing::error_message(
      [&] { NetDetector(default_field_of_view(120, 90), cpu, testing::test_device()); });
  EXPECT_NE(tiny.find("a 120x90 frame is below the 160x120 the ROI grid is planned for"),
            std::string::npos)
      << tiny;
  NetDetectorConfig given = cpu;
  given.grid.roi_size_px = 64;
  EXPECT_EQ(
      NetDetector(default_field_of_view(120, 90), given, testing::test_device()).config().fft_size,
      64);
  // A border that leaves no ROI.
  NetDetectorConfig bordered = cpu;
  bordered.grid.border_px = 110;
  const std::string border = testing::error_message(
      [&] { NetDetector(default_field_of_view(160, 120), bordered, testing::test_device()); });
  EXPECT_NE(border.find("a 160x120 frame with a border of 110 px leaves no room"),
            std::string::npos)
      << border;
}

}  // namespace
}  // namespace pensight
