// The run report: overlay PNGs on rendered nets, report.html of a synthetic run held in memory,
// and the page opened in headless Chromium (skipped where Debian's `chromium` is not installed).
#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <sstream>
#include <string>

#include "core/error.h"
#include "core/units.h"
#include "pipeline/dataset/diagnostics_csv.h"
#include "pipeline/dataset/estimates_csv.h"
#include "pipeline/fft/net_detector.h"
#include "tests/support/net_image.h"
#include "tests/support/vulkan_fixture.h"
#include "tools/report/overlay.h"
#include "tools/report/report_html.h"
#include "tools/timing_table.h"

namespace pensight {
namespace {
namespace fs = std::filesystem;

constexpr int64_t kFrame_ns = 100'000'000;  // 10 Hz
constexpr int64_t kStart_ns = 1'700'000'000'000'000'000;

std::string read_text(const fs::path& file) {
  std::ifstream in(file, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

size_t count(const std::string& text, const std::string& what) {
  size_t n = 0;
  for (size_t at = text.find(what); at != std::string::npos; at = text.find(what, at + 1)) ++n;
  return n;
}

class ReportTest : public ::testing::Test {
 protected:
  void SetUp() override {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    dir_ = fs::temp_directory_path() /
           ("pensight_report_test_" + std::to_string(::getpid()) + "_" + info->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }

  // Overlays of rendered nets through the real detector (CPU): near and square on, oblique, a
  // net that ends mid-frame (ROIs without a lattice) and open water (the pose NaN).
  void write_overlays(const fs::path& dir, int frames) const {
    fs::create_directories(dir);
    const PinholeCamera cam;
    NetDetector detector(cam, {.backend = Backend::kCpu, .cpu_threads = 1}, testing::test_device());
    for (int i = 0; i < frames; ++i) {
      testing::NetScene scene;
      scene.distance_m = 0.8 + 0.15 * i;
      scene.psi_rad = deg_to_rad(-20.0 + 10.0 * i);
      scene.seed = static_cast<uint64_t>(i + 1);
      if (i % 3 == 2) scene.edge_m = 0.1;
      const ImageU8 frame = i == frames - 1
                                ? testing::render_noise(cam.width_px, cam.height_px, 40, 90, 7)
                                : testing::render_net(cam, scene);
      const NetDetection d = detector.detect(frame, kStart_ns + i * kFrame_ns);
      char name[32];
      std::snprintf(name, sizeof name, "%06d.png", i);
      write_overlay_png(dir / name, frame, d);
    }
  }

  // A synthetic run into `out`: the vehicle passes along the net of a 12 m pen at r 11 m,
  // turning, on dataset_. Without optional_parts only the estimates are there; with them, the
  // published node's poses, diagnostics, timing and overlay PNGs in out/overlays.
  ReportInput synthetic_run(const fs::path& out, bool optional_parts) {
    Dataset& ds = dataset_;
    ds.root = "synthetic-dataset";
    ds.scene.pen_radius_m = 12;
    ds.groundtruth0.emplace();
    std::vector<EstimateRow> estimates, published;
    std::vector<DiagnosticsRow> diagnostics;
    const double rho0 = 0.4;
    for (int i = 0; i < 80; ++i) {
      const int64_t t = kStart_ns + i * kFrame_ns;
      const double s = 0.1 * i;
      GroundTruthRow g;
      g.timestamp_ns = t;
      const double rho = rho0 + 0.02 * s, r = 11.0 - 0.05 * std::sin(s);
      g.p_pen_body_m = {r * std::cos(rho), r * std::sin(rho), 3.0 + 0.1 * s};
      g.yaw_rad = rho + 0.1 * std::sin(0.5 * s);
      g.d_net_m = 12.0 - r;
      g.psi_net_rad = 0.1 * std::sin(0.5 * s);
      g.pitch_net_rad = 0.02;
      g.net_fraction = 1;
      ds.groundtruth0->rows.push_back(g);

      const bool nan_frame = i % 9 == 4;
      EstimateRow e;
      e.timestamp_ns = t;
      e.valid_rois = nan_frame ? 3 : 27;
      if (!nan_frame) {
        e.d_net_fft_m = g.d_net_m * (1 + 0.01 * std::sin(3.0 * s));
        e.psi_net_fft_rad = g.psi_net_rad + deg_to_rad(0.5) * std::sin(2.0 * s);
        e.pitch_net_fft_rad = g.pitch_net_rad - deg_to_rad(0.3);
      }
      e.r_g_m = r + 0.01;
      e.rho_g_rad = rho - rho0 + 0.001 * s;
      e.z_g_m = g.p_pen_body_m.z() + 0.005;
      e.psi_g_rad = g.yaw_rad - rho0 + deg_to_rad(0.2);
      estimates.push_back(e);
      EstimateRow p = e;
      p.rho_g_rad = rho - rho0 + 0.01 * s;
      p.r_g_m = r - 0.05;
      published.push_back(p);

      DiagnosticsRow d{.timestamp_ns = t, .valid_rois = e.valid_rois};
      d.inlier_rois = nan_frame ? 0 : 25;
      d.plane_rms_m = nan_frame ? kNaN : 0.004;
      if (nan_frame) d.fft_reason = i % 2 ? "too few ROIs <3> & no plane" : "open water";
      d.dvl_plane_d_m = g.d_net_m + 0.03;
      d.dvl_plane_psi_rad = i % 4 ? g.psi_net_rad : kNaN;
      for (int k = 0; k < static_cast<int>(kDiagnosticsSensors.size()); ++k) {
        d.accepted[static_cast<size_t>(k)] = (k + i) % 3;
        d.rejected[static_cast<size_t>(k)] = k == 1 && i % 7;
      }
      diagnostics.push_back(d);
    }
    ReportInput run{.out_dir = out, .dataset = &ds, .estimates = std::move(estimates)};
    if (!optional_parts) return run;
    run.published = std::move(published);
    run.diagnostics = std::move(diagnostics);
    const std::vector<StageStats> stages = {
        {"fft net detection", 80, 0, 4.61, 5.2, 9.8, 10, 4.7, 5.4},
        {"relative pose (fft)", 80, 0, 0.31, 0.4, 0.9, 10, 5.1, 5.8},
        {"global pose", 80, 0, 0.02, 0.03, 0.05, 10, 5.2, 5.9}};
    run.timing = timing_table(stages);
    write_overlays(out / "overlays", 7);
    return run;
  }

  fs::path dir_;
  Dataset dataset_;
};

TEST_F(ReportTest, OverlayIsAColourPngOfTheFrameWithTheRoiGrid) {
  const PinholeCamera cam;
  const ImageU8 frame(cam.width_px, cam.height_px, 128);
  const auto rois = kernels::roi_grid(cam.width_px, cam.height_px, {});
  NetDetection d;
  d.rois = rois;
  d.roi_size_px = 300;
  d.points.resize(rois.size());
  d.pose = {FftPoseStatus::kValid,
            1.2,
            0.1,
            0.0,
            20,
            10,
            0.003,
            std::vector<uint8_t>(rois.size(), 0),
            ""};
  for (size_t i = 0; i < rois.size(); ++i) {
    RoiNetPoint& p = d.points[i];
    p.centre_px = {rois[i].x + 149.5, rois[i].y + 149.5};
    if (i >= 20) continue;  // no lattice
    p.status = RoiStatus::kValid;
    p.lattice1_px = {14, 2};
    p.lattice2_px = {-2, 15};
    d.pose.inlier[i] = i < 10;
  }
  const fs::path file = dir_ / "overlay.png";
  write_overlay_png(file, frame, d);
  const cv::Mat image = cv::imread(file.string(), cv::IMREAD_UNCHANGED);
  ASSERT_FALSE(image.empty());
  EXPECT_EQ(image.cols, cam.width_px);
  EXPECT_EQ(image.rows, cam.height_px);
  EXPECT_EQ(image.channels(), 3);
  // Every ROI's left and right borders, half way down, are coloured (not the frame's grey).
  for (const kernels::RoiOrigin& o : rois) {
    for (const int x : {o.x, o.x + 299}) {
      const cv::Vec3b px = image.at<cv::Vec3b>(o.y + 150, x);
      EXPECT_FALSE(px[0] == 128 && px[1] == 128 && px[2] == 128) << "at " << x << "," << o.y + 150;
    }
  }

  d.points.pop_back();
  EXPECT_THROW(write_overlay_png(file, frame, d), Error);
  EXPECT_THROW(write_overlay_png(file, ImageU8{}, d), Error);
}

TEST_F(ReportTest, OverlaysOfDetectedNets) {
  write_overlays(dir_, 4);
  for (int i = 0; i < 4; ++i) {
    char name[32];
    std::snprintf(name, sizeof name, "%06d.png", i);
    const cv::Mat image = cv::imread((dir_ / name).string(), cv::IMREAD_COLOR);
    ASSERT_FALSE(image.empty()) << name;
    EXPECT_EQ(image.cols, 720);
    EXPECT_EQ(image.rows, 540);
  }
  EXPECT_EQ(std::distance(fs::directory_iterator(dir_), fs::directory_iterator{}), 4)
      << "only the PNGs, no temporary files";
}

TEST_F(ReportTest, ReportHasEverySectionAndFetchesNothing) {
  write_report_html(synthetic_run(dir_, true));
  const std::string html = read_text(dir_ / "report.html");
  for (const char* section :
       {"Net-relative pose (FFT)", "Global pose in the pen", "Track in the pen, seen from above",
        "Errors against the ground truth", "Diagnostics", "Per-stage timing", "Overlay frames",
        "DVL net plane", "published node", "fft net detection", "d_net     rel. error"}) {
    EXPECT_NE(html.find(section), std::string::npos) << section;
  }
  EXPECT_EQ(html.find("not written by this run"), std::string::npos);
  EXPECT_EQ(count(html, "<svg width="), 10u);  // 3 net pose, 4 global pose, 2 top views, ROIs
  EXPECT_EQ(count(html, "<img src=\"data:image/jpeg;base64,"), 4u);
  for (const char* shown : {"000000.png", "000002.png", "000004.png", "000006.png"}) {
    EXPECT_NE(html.find(shown), std::string::npos) << shown;  // evenly spaced, first and last
  }
  EXPECT_EQ(html.find("http"), std::string::npos);
  EXPECT_EQ(html.find("src=\"//"), std::string::npos);
  // NaN reasons counted per reason, escaped.
  EXPECT_NE(html.find("too few ROIs &lt;3&gt; &amp; no plane</td><td class=\"n\">4<"),
            std::string::npos);
  EXPECT_NE(html.find("open water</td><td class=\"n\">5<"), std::string::npos);
  EXPECT_EQ(html.find("<3>"), std::string::npos);
}

TEST_F(ReportTest, OptionalPartsAbsent) {
  ReportInput run = synthetic_run(dir_, false);
  run.dataset = nullptr;
  write_report_html(run);
  const std::string html = read_text(dir_ / "report.html");
  for (const char* absent :
       {"diagnostics.csv was not written by this run", "timing.csv was not written by this run",
        "overlays/*.png were not written by this run",
        "global_pose_published.csv was not written by this run",
        "No dataset given: no ground truth"}) {
    EXPECT_NE(html.find(absent), std::string::npos) << absent;
  }
  EXPECT_EQ(html.find("<img"), std::string::npos);

  // Ground truth without groundtruth0, and timing rows of nodes that did not run: no figures.
  Dataset no_truth;
  run.dataset = &no_truth;
  run.timing = timing_table({});
  write_report_html(run);
  const std::string again = read_text(dir_ / "report.html");
  EXPECT_NE(again.find("The dataset has no groundtruth0/"), std::string::npos);
  EXPECT_NE(again.find("<tr><td>global pose</td><td class=\"n\">0</td><td class=\"n\">n/a</td>"),
            std::string::npos);
  EXPECT_EQ(again.find("timing.csv was not written by this run"), std::string::npos);
}

// A bag run through a temporary dataset folder: the page names the bag, not the folder.
TEST_F(ReportTest, NamesTheInputWhenItWasNotTheDatasetFolder) {
  ReportInput run = synthetic_run(dir_, false);
  Dataset converted;
  converted.root = dir_ / ".bag_dataset";
  run.dataset = &converted;
  run.input = "dives/net <3>.bag";
  write_report_html(run);
  const std::string html = read_text(dir_ / "report.html");
  EXPECT_NE(html.find("Input: <code>dives/net &lt;3&gt;.bag</code>"), std::string::npos);
  EXPECT_EQ(html.find(".bag_dataset"), std::string::npos);
}

TEST_F(ReportTest, EmptyAndAllNanRuns) {
  ReportInput run{.out_dir = dir_, .estimates = std::vector<EstimateRow>{}};
  write_report_html(run);
  EXPECT_NE(read_text(dir_ / "report.html").find("0 frames over 0.0 s"), std::string::npos);

  for (int i = 0; i < 3; ++i) run.estimates->push_back({.timestamp_ns = kStart_ns + i * kFrame_ns});
  write_report_html(run);
  const std::string html = read_text(dir_ / "report.html");
  EXPECT_NE(html.find("3 frames over 0.2 s"), std::string::npos);
  for (const char* bad : {"nan", "inf"}) {
    EXPECT_EQ(html.find(bad), std::string::npos) << "no " << bad << " coordinates or labels";
  }
}

TEST_F(ReportTest, MissingEstimatesIsAnErrorNamingIt) {
  try {
    write_report_html({.out_dir = dir_});
    FAIL() << "no error without estimates";
  } catch (const Error& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find(dir_.string()), std::string::npos) << what;
    EXPECT_NE(what.find("estimates"), std::string::npos) << what;
    EXPECT_NE(what.find("pensight run"), std::string::npos) << what;
  }
  EXPECT_FALSE(fs::exists(dir_ / "report.html"));
}

// Debian's Chromium, headless, as a user would open the page; a fresh profile per call.
class HeadlessChromium {
 public:
  static constexpr const char* kPath = "/usr/bin/chromium";
  explicit HeadlessChromium(fs::path work) : work_(std::move(work)) {}

  // The page's own verdict (<html data-self-check="ok"> or "failed: ..."; empty when the check
  // did not run) and Chromium's console log.
  std::pair<std::string, std::string> self_check(const fs::path& page) {
    const fs::path dom = next("dom.html"), log = next("dom.log");
    run("--dump-dom file://" + page.string() + " > " + dom.string() + " 2> " + log.string(), log);
    const std::string html = read_text(dom), marker = "data-self-check=\"";
    const size_t at = html.find(marker);
    if (at == std::string::npos) return {"", read_text(log)};
    const size_t value = at + marker.size();
    return {html.substr(value, html.find('"', value) - value), read_text(log)};
  }
  void screenshot(const fs::path& page, const fs::path& png) {
    const fs::path log = next("shot.log");
    run("--screenshot=" + png.string() + " file://" + page.string() + " > " + log.string() +
            " 2>&1",
        log);
  }

 private:
  fs::path next(const std::string& name) { return work_ / (std::to_string(runs_) + "_" + name); }
  void run(const std::string& args, const fs::path& log) {
    const std::string command =
        std::string("timeout 120 ") + kPath +
        " --headless --no-sandbox --disable-gpu --disable-quic --no-first-run"
        " --disable-background-networking --disable-component-update --disable-sync"
        " --enable-logging=stderr --v=0 --virtual-time-budget=10000 --window-size=1200,3000"
        " --user-data-dir=" +
        next("profile").string() + " " + args;
    ++runs_;
    ASSERT_EQ(std::system(command.c_str()), 0) << command << "\n" << read_text(log);
  }

  fs::path work_;
  int runs_ = 0;
};

// Every image must decode and no script may fail: the page checks that itself once loaded, and
// Chromium's console log must hold no uncaught error. A page with a broken image and a failing
// script shows that the check sees both. PENSIGHT_REPORT_TEST_OUT=DIR keeps the page and its
// screenshot there to look at.
TEST_F(ReportTest, OpensInHeadlessChromium) {
  if (!fs::exists(HeadlessChromium::kPath)) {
    GTEST_SKIP() << "no " << HeadlessChromium::kPath
                 << ": apt-get install chromium (scripts/packages.txt) to open the report";
  }
  const fs::path out = dir_ / "OUT";
  fs::create_directories(out);
  write_report_html(synthetic_run(out, true));
  HeadlessChromium chromium(dir_);

  const auto [verdict, log] = chromium.self_check(out / "report.html");
  EXPECT_EQ(verdict, "ok") << log;
  EXPECT_EQ(log.find("Uncaught"), std::string::npos) << log;

  const fs::path shot = dir_ / "shot.png";
  chromium.screenshot(out / "report.html", shot);
  const cv::Mat image = cv::imread(shot.string(), cv::IMREAD_COLOR);
  ASSERT_FALSE(image.empty());
  EXPECT_EQ(image.cols, 1200);
  EXPECT_EQ(image.rows, 3000);
  if (const char* keep = std::getenv("PENSIGHT_REPORT_TEST_OUT")) {
    fs::create_directories(keep);
    fs::copy_file(out / "report.html", fs::path(keep) / "report.html",
                  fs::copy_options::overwrite_existing);
    fs::copy_file(shot, fs::path(keep) / "shot.png", fs::copy_options::overwrite_existing);
  }

  std::string broken = read_text(out / "report.html");
  const size_t png = broken.find("base64,") + 7;
  broken.replace(png, 16, "////////////////");
  broken.insert(broken.find("</body>"), "<script>no_such_function();</script>\n");
  std::ofstream(dir_ / "broken.html") << broken;
  const auto [broken_verdict, broken_log] = chromium.self_check(dir_ / "broken.html");
  EXPECT_EQ(broken_verdict.rfind("failed: ", 0), 0u) << broken_verdict;
  EXPECT_NE(broken_verdict.find("no_such_function"), std::string::npos) << broken_verdict;
  EXPECT_NE(broken_verdict.find("broken image 000000.png"), std::string::npos) << broken_verdict;
  EXPECT_NE(broken_log.find("Uncaught"), std::string::npos) << broken_log;
}

}  // namespace
}  // namespace pensight
