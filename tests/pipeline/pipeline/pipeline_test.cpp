#include "pipeline/pipeline.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <atomic>
#include <chrono>
#include <cmath>
#include <future>
#include <mutex>
#include <optional>
#include <random>
#include <thread>

#include "core/csv.h"
#include "core/error.h"
#include "pipeline/dataset/diagnostics_csv.h"
#include "pipeline/dataset/png_io.h"
#include "pipeline/dataset/trajectory_tum.h"
#include "tests/support/depth_models.h"
#include "tests/support/net_image.h"
#include "tests/support/rendered_run.h"
#include "tests/support/vulkan_fixture.h"
#include "tools/runner.h"

namespace pensight {
namespace {

using testing::test_device;

// The same text in estimates.csv (the replay's rows are read back from it).
bool same(double a, double b) {
  return format_number(a) == format_number(b);
}

PipelineConfig config_for(const PinholeCamera& cam) {
  PipelineConfig c;
  c.camera = cam;
  c.detector.backend = Backend::kCpu;
  c.detector.cpu_threads = 1;  // OpenMP's runtime is not instrumented for ThreadSanitizer
  c.global_pose.pen_radius_m = 100;
  c.global_pose.dvl_beams.reset();
  return c;
}

// Net frames at distances drawn from `rng`, 10 Hz from t0.
struct Sequence {
  std::vector<CameraFrame> frames;
  std::vector<DvlSample> dvl;
  std::vector<PressureSample> depth;
  std::vector<AttitudeSample> attitude;
};

constexpr int64_t kT0 = 1'600'000'000'000'000'000;
constexpr int64_t kMs = 1'000'000;

Sequence sequence(const PinholeCamera& cam, int frames, std::mt19937_64& rng) {
  Sequence s;
  std::uniform_real_distribution<double> distance(0.7, 1.8), angle(-0.3, 0.3);
  for (int i = 0; i < frames; ++i) {
    const testing::NetScene scene{.distance_m = distance(rng),
                                  .psi_rad = angle(rng),
                                  .pitch_rad = angle(rng) / 3,
                                  .seed = rng()};
    s.frames.push_back({kT0 + i * 100 * kMs, testing::render_net(cam, scene)});
  }
  const int64_t end = kT0 + frames * 100 * kMs;
  for (int64_t t = kT0 - 40 * kMs; t < end; t += 250 * kMs) {
    s.dvl.push_back({.timestamp_ns = t, .velocity_B_mps = {0.0, 0.1, 0.0}, .valid = true});
  }
  for (int64_t t = kT0 - 20 * kMs; t < end; t += 100 * kMs) {
    s.depth.push_back({.timestamp_ns = t, .depth_m = 2.0});
  }
  for (int64_t t = kT0 - 30 * kMs; t < end; t += 50 * kMs) {
    s.attitude.push_back({.timestamp_ns = t, .roll_rad = 0, .pitch_rad = 0, .yaw_rad = 0.1});
  }
  return s;
}

// Collects the results delivered to on_frame.
struct Collector {
  std::mutex mutex;
  std::vector<FrameResult> results;
  void add(const FrameResult& r) {
    std::lock_guard lock(mutex);
    results.push_back(r);
  }
};

// The stages called one after another, as run_dataset did before it replayed through Pipeline.
std::vector<EstimateRow> direct_rows(const Dataset& d) {
  NetDetector detector(d.cam0.camera, detector_config(d.scene, {.backend = Backend::kCpu}),
                       test_device());
  global_pose::GlobalPoseEstimator est(global_pose_config(d));
  size_t dvl = 0, depth = 0, att = 0;
  std::vector<EstimateRow> rows;
  for (size_t i = 0; i < d.frames.size(); ++i) {
    EstimateRow row;
    row.timestamp_ns = d.frames[i].timestamp_ns;
    const NetDetection det = detector.detect(d.load_frame(i), row.timestamp_ns);
    row.valid_rois = det.pose.valid_rois;
    if (det.pose.valid()) {
      row.d_net_fft_m = det.pose.d_net_m;
      row.psi_net_fft_rad = det.pose.psi_net_rad;
      row.pitch_net_fft_rad = det.pose.pitch_net_rad;
    }
    for (; d.dvl0 && dvl < d.dvl0->samples.size() &&
           d.dvl0->samples[dvl].timestamp_ns <= row.timestamp_ns;
         ++dvl)
      est.add(d.dvl0->samples[dvl]);
    for (; d.pressure0 && depth < d.pressure0->size() &&
           (*d.pressure0)[depth].timestamp_ns <= row.timestamp_ns;
         ++depth)
      est.add((*d.pressure0)[depth]);
    for (; d.imu0 && att < d.imu0->size() && (*d.imu0)[att].timestamp_ns <= row.timestamp_ns; ++att)
      est.add((*d.imu0)[att]);
    est.add(net_observation(det));
    const global_pose::GlobalPose g = est.estimate(row.timestamp_ns);
    row.r_g_m = g.r_g_m;
    row.rho_g_rad = g.rho_g_rad;
    row.z_g_m = g.z_g_m;
    row.psi_g_rad = g.psi_g_rad;
    rows.push_back(row);
  }
  return rows;
}

// trajectory_tum.txt beside estimates.csv: a line for each row with the whole global pose and
// none for the others, in order, with the same timestamps; position (r_g cos rho_g, r_g sin rho_g,
// z_g) and yaw psi_g as far as estimates.csv's 9 digits keep them (1e-6 m and rad: 1000x their
// rounding); roll and pitch within 5 sigma (0.015 rad) of the truth, the attitude sensor's noise
// being 0.003 rad. Returns the number of lines.
size_t expect_trajectory_matches(const Dataset& d, const std::vector<EstimateRow>& rows,
                                 const std::vector<TumPose>& trajectory) {
  size_t next = 0;
  for (size_t i = 0; i < rows.size(); ++i) {
    const EstimateRow& r = rows[i];
    if (!std::isfinite(r.r_g_m) || !std::isfinite(r.rho_g_rad) || !std::isfinite(r.z_g_m) ||
        !std::isfinite(r.psi_g_rad))
      continue;
    if (next == trajectory.size()) {
      ADD_FAILURE() << "no trajectory line for frame " << i;
      return next;
    }
    const TumPose& p = trajectory[next++];
    EXPECT_EQ(p.timestamp_ns, r.timestamp_ns) << "frame " << i;
    EXPECT_NEAR(p.p_m.x(), r.r_g_m * std::cos(r.rho_g_rad), 1e-6) << "frame " << i;
    EXPECT_NEAR(p.p_m.y(), r.r_g_m * std::sin(r.rho_g_rad), 1e-6) << "frame " << i;
    EXPECT_NEAR(p.p_m.z(), r.z_g_m, 1e-6) << "frame " << i;
    EXPECT_GE(p.q.w(), 0);
    EXPECT_NEAR(p.q.norm(), 1, 1e-8);
    const Eigen::Matrix3d R = p.q.normalized().toRotationMatrix();
    EXPECT_NEAR(wrap_angle(std::atan2(R(1, 0), R(0, 0)) - r.psi_g_rad), 0, 1e-6) << "frame " << i;
    const GroundTruthRow* t = d.truth_for_frame(i);
    if (!t) {
      ADD_FAILURE() << "no truth for frame " << i;
      continue;
    }
    EXPECT_NEAR(-std::asin(R(2, 0)), t->pitch_rad, 0.015) << "frame " << i;
    EXPECT_NEAR(std::atan2(R(2, 1), R(2, 2)), t->roll_rad, 0.015) << "frame " << i;
  }
  EXPECT_EQ(next, trajectory.size()) << "lines for frames without a pose";
  return trajectory.size();
}

// `pensight run` replays the dataset through Pipeline; its estimates.csv is that of the direct
// calls, to the last written digit.
TEST(Pipeline, ReplayOfARenderedSequenceEqualsTheDirectCalls) {
  const testing::RenderedDataset rendered(testing::shipped_scenario("follow.yaml", 2.0));
  const testing::RenderedRun run = rendered.run(rendered.dataset(), "replay");
  const std::vector<EstimateRow> direct = direct_rows(rendered.dataset());
  ASSERT_EQ(run.rows.size(), direct.size());
  int with_pose = 0, with_r_g = 0;
  for (size_t i = 0; i < direct.size(); ++i) {
    const EstimateRow &a = run.rows[i], &b = direct[i];
    EXPECT_EQ(a.timestamp_ns, b.timestamp_ns);
    EXPECT_EQ(a.valid_rois, b.valid_rois) << i;
    for (const auto& [x, y] : {std::pair{a.d_net_fft_m, b.d_net_fft_m},
                               {a.psi_net_fft_rad, b.psi_net_fft_rad},
                               {a.pitch_net_fft_rad, b.pitch_net_fft_rad},
                               {a.r_g_m, b.r_g_m},
                               {a.rho_g_rad, b.rho_g_rad},
                               {a.z_g_m, b.z_g_m},
                               {a.psi_g_rad, b.psi_g_rad}}) {
      EXPECT_TRUE(same(x, y)) << "frame " << i << ": " << x << " vs " << y;
    }
    with_pose += std::isfinite(b.d_net_fft_m);
    with_r_g += std::isfinite(b.r_g_m);
  }
  // Not a comparison of NaNs: the sequence follows the net, so most frames have both.
  EXPECT_GE(with_pose, static_cast<int>(direct.size()) - 2);
  EXPECT_GE(with_r_g, static_cast<int>(direct.size()) / 2);
  EXPECT_GE(expect_trajectory_matches(run.dataset, run.rows, run.trajectory), direct.size() / 2);
}

// The start of the sweep faces open water, then turns onto the net: diagnostics.csv says why each
// NaN frame is NaN, timing.csv has the published nodes beside ours, report.html shows overlays.
TEST(Pipeline, RunWritesDiagnosticsAndTiming) {
  const testing::RenderedDataset rendered(testing::shipped_scenario("sweep.yaml", 1.5));
  const Dataset& d = rendered.dataset();
  const std::filesystem::path out =
      std::filesystem::temp_directory_path() / ("pensight-diag-" + std::to_string(::getpid()));
  RunOptions options;
  options.detector.backend = Backend::kCpu;
  const RunSummary summary = run_dataset(d, out, options, test_device());
  const std::vector<EstimateRow> rows = read_estimates_csv(out / "estimates.csv");
  // 8 leading columns, an accepted and a rejected one per sensor, mesh_type, reduced_rois,
  // depth_scale, dvl_depth_ratio, the four of the DVL's tilt and fft_quality.
  const size_t columns = 8 + 2 * kDiagnosticsSensors.size() + 9;
  const CsvTable diag(out / kDiagnosticsFile, columns, columns);
  ASSERT_EQ(diag.rows(), d.frames.size());
  int nan_frames = 0;
  for (size_t i = 0; i < diag.rows(); ++i) {
    EXPECT_EQ(diag.integer(i, 0), d.frames[i].timestamp_ns);
    EXPECT_EQ(diag.integer(i, 1), rows[i].valid_rois);
    const bool has_pose = std::isfinite(rows[i].d_net_fft_m);
    EXPECT_EQ(diag.text(i, 4).empty(), has_pose) << i << ": " << diag.text(i, 4);
    const double quality = diag.number(i, columns - 1);
    if (has_pose) {
      EXPECT_GE(diag.integer(i, 2), 6);
      EXPECT_GT(quality, 0) << i;
      EXPECT_LE(quality, 1) << i;
    } else {
      EXPECT_EQ(quality, 0) << i;
    }
    nan_frames += !has_pose;
    // One pressure sample per frame at 10 Hz: each row counts it.
    EXPECT_EQ(diag.integer(i, 12) + diag.integer(i, 13), 1) << i;
  }
  EXPECT_GT(nan_frames, 0);
  EXPECT_LT(nan_frames, static_cast<int>(diag.rows()));
  // The frames facing open water have no pose and no trajectory line.
  const size_t lines =
      expect_trajectory_matches(d, rows, read_trajectory_tum(out / kTrajectoryTumFile));
  EXPECT_GT(lines, 0u);
  EXPECT_LT(lines, rows.size());
  const CsvTable timing(out / kTimingFile, 10, 10);
  bool fft = false, orin = false;
  for (size_t i = 0; i < timing.rows(); ++i) {
    if (timing.text(i, 0) == "fft net detection") {
      fft = timing.integer(i, 1) == static_cast<int64_t>(d.frames.size());
      orin = timing.number(i, 8) == 47.8;
    }
  }
  EXPECT_TRUE(fft && orin);
  EXPECT_EQ(summary.timing.size(), timing.rows());
  EXPECT_FALSE(std::filesystem::exists(out / "depth"));  // no model, no dense-depth stage
  // The report and the overlays it shows (kReportOverlays evenly spaced frames, the first one).
  EXPECT_TRUE(std::filesystem::is_regular_file(out / "report.html"));
  size_t overlays = 0;
  for (const auto& e : std::filesystem::directory_iterator(out / "overlays"))
    overlays += e.is_regular_file();
  EXPECT_EQ(overlays, kReportOverlays);
  EXPECT_TRUE(std::filesystem::is_regular_file(
      out / "overlays" / (std::filesystem::path(d.frames[0].filename).stem().string() + ".png")));
  std::filesystem::remove_all(out);
}

// With a depth model: OUT/depth/<cam0 file> (16-bit mm, the camera's size) for every frame with an
// FFT pose and none for the others, the *_depth columns filled on the same frames, and the stage
// in timing.csv. The S1 model outputs the nearest prior, so its depth follows the rendered net.
TEST(Pipeline, RunWithTheDepthStageWritesDepthPngsAndColumns) {
  const testing::RenderedDataset rendered(testing::shipped_scenario("sweep.yaml", 1.5));
  const Dataset& d = rendered.dataset();
  const std::filesystem::path out =
      std::filesystem::temp_directory_path() / ("pensight-depth-" + std::to_string(::getpid()));
  std::filesystem::create_directories(out);
  testing::write_s1_depth_model(out / "s1.onnx", 320, 240);
  RunOptions options;
  options.detector.backend = Backend::kCpu;
  // The engine's executor: OpenCV DNN's own thread pool is not instrumented for ThreadSanitizer
  // (depth_estimator_test covers that backend).
  options.depth = DepthEstimatorConfig{
      .model = out / "s1.onnx", .backend = Backend::kCpu, .cpu_inference = CpuInference::kEngine};
  const RunSummary summary = run_dataset(d, out, options, test_device());
  const std::vector<EstimateRow> rows = read_estimates_csv(out / "estimates.csv");
  ASSERT_EQ(rows.size(), d.frames.size());
  size_t with_depth = 0, frontal = 0;
  for (size_t i = 0; i < rows.size(); ++i) {
    const bool fft = std::isfinite(rows[i].d_net_fft_m);
    const std::filesystem::path png = out / "depth" / d.frames[i].filename;
    ASSERT_EQ(std::filesystem::exists(png), fft) << i;
    EXPECT_EQ(std::isfinite(rows[i].d_net_depth_m), fft) << i;
    if (!fft) continue;
    ++with_depth;
    // S1 is constant around each prior: beyond ~30 deg of obliquity a prior's patch spans more
    // depth than these bounds (the sweep turns to 50 deg).
    if (std::abs(rows[i].psi_net_fft_rad) > 0.5) continue;
    ++frontal;
    EXPECT_NEAR(rows[i].d_net_depth_m, rows[i].d_net_fft_m, 0.05 * rows[i].d_net_fft_m) << i;
    EXPECT_NEAR(rows[i].psi_net_depth_rad, rows[i].psi_net_fft_rad, 0.05) << i;
    const ImageU16 mm = read_png_u16(png, d.cam0.camera.width_px, d.cam0.camera.height_px);
    const ImageU16 truth = d.load_depth_mm(i);
    int close = 0, compared = 0;
    for (size_t p = 0; p < mm.pixels.size(); p += 97) {
      if (truth.pixels[p] == 0) continue;
      ++compared;
      close += std::abs(mm.pixels[p] - truth.pixels[p]) < 0.05 * truth.pixels[p];
    }
    EXPECT_GT(close, 0.8 * compared) << i;
  }
  EXPECT_GT(frontal, 3u);
  EXPECT_EQ(summary.frames_with_depth, with_depth);
  EXPECT_NE(summary.depth_backend.find("320x240"), std::string::npos) << summary.depth_backend;
  const CsvTable timing(out / kTimingFile, 10, 10);
  bool dense = false;
  for (size_t i = 0; i < timing.rows(); ++i) {
    if (timing.text(i, 0) == "dense depth") {
      dense =
          timing.integer(i, 1) == static_cast<int64_t>(with_depth) && timing.number(i, 8) == 66.8;
    }
  }
  EXPECT_TRUE(dense);
  std::filesystem::remove_all(out);
}

// Camera frames from one thread, each sensor from its own, shuffled within a few samples: every
// frame comes back once, in order, and every sample reaches the estimator.
TEST(Pipeline, PushesFromSeveralThreadsAndOutOfOrderLoseNothing) {
  std::mt19937_64 rng(testing::fresh_seed());
  const PinholeCamera cam;
  Sequence s = sequence(cam, 12, rng);
  auto shuffle_locally = [&](auto& v) {
    for (size_t i = 0; i + 2 < v.size(); i += 3)
      std::shuffle(v.begin() + i, v.begin() + i + 3, rng);
  };
  shuffle_locally(s.dvl);
  shuffle_locally(s.depth);
  shuffle_locally(s.attitude);
  Collector out;
  PipelineConfig c = config_for(cam);
  c.on_frame = [&](const FrameResult& r) { out.add(r); };
  Pipeline p(c, test_device());
  std::vector<std::thread> threads;
  threads.emplace_back([&] {
    for (const auto& x : s.dvl) p.push(x);
  });
  threads.emplace_back([&] {
    for (const auto& x : s.depth) p.push(x);
  });
  threads.emplace_back([&] {
    for (const auto& x : s.attitude) p.push(x);
  });
  for (CameraFrame& f : s.frames) p.push(CameraFrame{f.timestamp_ns, f.image});
  for (auto& t : threads) t.join();
  p.finish();

  ASSERT_EQ(out.results.size(), s.frames.size());
  for (size_t i = 0; i < s.frames.size(); ++i) {
    EXPECT_EQ(out.results[i].timestamp_ns, s.frames[i].timestamp_ns);
    EXPECT_TRUE(out.results[i].error.empty()) << out.results[i].error;
    ASSERT_TRUE(out.results[i].image);
    EXPECT_EQ(out.results[i].image->pixels, s.frames[i].image.pixels);
    EXPECT_TRUE(out.results[i].detection.pose.valid()) << out.results[i].detection.pose.reason;
  }
  const global_pose::GlobalPoseCounters c2 = p.global_pose_counters();
  EXPECT_EQ(c2.dvl_velocity.received, static_cast<int>(s.dvl.size()));
  EXPECT_EQ(c2.depth.received, static_cast<int>(s.depth.size()));
  EXPECT_EQ(c2.attitude.received, static_cast<int>(s.attitude.size()));
  EXPECT_EQ(c2.vision_fix.received, static_cast<int>(s.frames.size()));
  const std::vector<StageStats> st = p.stats();
  EXPECT_EQ(st[0].name, "fft net detection");
  EXPECT_EQ(st[0].processed, s.frames.size());
  EXPECT_EQ(st[2].processed, s.frames.size());
  EXPECT_EQ(st[3].dropped, 0u);
  EXPECT_GE(st[2].latency_mean_ms, st[0].latency_mean_ms);
}

// A consumer that stops taking results makes the result queue drop its oldest ones (counted,
// bounded); the pose path goes on processing every frame meanwhile.
TEST(Pipeline, SlowConsumerGetsCountedDropsNotABlockedPosePath) {
  std::mt19937_64 rng(testing::fresh_seed());
  const PinholeCamera cam;
  const Sequence s = sequence(cam, 10, rng);
  std::promise<void> release;
  std::shared_future<void> released = release.get_future().share();
  std::atomic<int> delivered{0};
  PipelineConfig c = config_for(cam);
  c.result_queue = 2;
  c.on_frame = [&](const FrameResult&) {
    released.wait();
    ++delivered;
  };
  Pipeline p(c, test_device());
  for (const CameraFrame& f : s.frames) p.push(CameraFrame{f.timestamp_ns, f.image});
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::minutes(2);
  while (p.stats()[2].processed < s.frames.size() && std::chrono::steady_clock::now() < deadline) {
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  EXPECT_EQ(p.stats()[2].processed, s.frames.size()) << "the pose path waited for the consumer";
  EXPECT_EQ(delivered.load(), 0);
  release.set_value();
  p.finish();
  const StageStats delivery = p.stats()[3];
  // One result in the blocked callback, at most two queued; the rest dropped and counted.
  EXPECT_LE(delivered.load(), 3);
  EXPECT_EQ(static_cast<size_t>(delivered.load()) + delivery.dropped, s.frames.size());
}

// Without a callback the results wait for poll(), in frame order; a frame of the wrong size
// comes back with an error and leaves the estimators untouched.
TEST(Pipeline, PollDeliversResultsAndErrorsInOrder) {
  std::mt19937_64 rng(testing::fresh_seed());
  const PinholeCamera cam;
  const Sequence s = sequence(cam, 3, rng);
  PipelineConfig c = config_for(cam);
  Pipeline p(c, test_device());
  p.push(CameraFrame{s.frames[0].timestamp_ns, s.frames[0].image});
  p.push(CameraFrame{s.frames[1].timestamp_ns, ImageU8(64, 48)});
  p.push(CameraFrame{s.frames[2].timestamp_ns, s.frames[2].image});
  p.finish();
  std::vector<FrameResult> got;
  while (auto r = p.poll()) got.push_back(std::move(*r));
  ASSERT_EQ(got.size(), 3u);
  EXPECT_TRUE(got[0].error.empty());
  EXPECT_NE(got[1].error.find("64x48"), std::string::npos) << got[1].error;
  EXPECT_TRUE(got[2].error.empty());
  EXPECT_EQ(got[2].timestamp_ns, s.frames[2].timestamp_ns);
  EXPECT_EQ(p.global_pose_counters().vision_fix.received, 2);
}

// A pressure sample due at a frame's time that arrives after the frame (as over a live topic) is
// used for that frame when the pipeline waits for due samples, and is late for it otherwise.
TEST(Pipeline, SensorWaitUsesASampleThatArrivesJustAfterItsFrame) {
  std::mt19937_64 rng(testing::fresh_seed());
  const PinholeCamera cam;
  const Sequence s = sequence(cam, 1, rng);
  const int64_t t = s.frames[0].timestamp_ns;
  std::uniform_real_distribution<double> depth_m(2, 20);
  const double late_depth_m = depth_m(rng);
  for (const double wait_ms : {0.0, 10000.0}) {
    PipelineConfig c = config_for(cam);
    c.sensor_wait_ms = wait_ms;
    Pipeline p(c, test_device());
    for (int k = 5; k >= 1; --k) p.push(PressureSample{t - 100 * kMs * k, 1.0});
    p.push(CameraFrame{t, s.frames[0].image});
    std::optional<FrameResult> r;
    if (wait_ms == 0) {  // the frame's result comes without the sample
      for (int i = 0; i < 3000 && !r; ++i) {
        std::this_thread::sleep_for(std::chrono::milliseconds(10));
        r = p.poll();
      }
    } else {  // the worker waits: the result comes after the sample
      std::this_thread::sleep_for(std::chrono::milliseconds(300));
      EXPECT_FALSE(p.poll());
    }
    p.push(PressureSample{t, late_depth_m});
    p.finish();
    if (!r) r = p.poll();
    ASSERT_TRUE(r);
    EXPECT_EQ(r->global_pose.z_g_m, wait_ms > 0 ? late_depth_m : 1.0) << "wait " << wait_ms;
  }
}

// A callback that throws loses its own result only: delivery goes on.
TEST(Pipeline, ThrowingCallbackDoesNotStopDelivery) {
  std::mt19937_64 rng(testing::fresh_seed());
  const PinholeCamera cam;
  const Sequence s = sequence(cam, 3, rng);
  std::atomic<int> calls{0};
  PipelineConfig c = config_for(cam);
  c.on_frame = [&](const FrameResult&) {
    if (calls++ == 0) throw Error("the caller's own failure");
  };
  Pipeline p(c, test_device());
  for (const CameraFrame& f : s.frames) p.push(CameraFrame{f.timestamp_ns, f.image});
  p.finish();
  EXPECT_EQ(calls.load(), 3);
}

// A lost device ends the run: the frames before it have their results, then push() or finish()
// throws DeviceLostError naming the frame and the call, and no later frame gets a row of NaN.
TEST(Pipeline, LostDeviceEndsTheRunWithAClearError) {
  std::mt19937_64 rng(testing::fresh_seed());
  const PinholeCamera cam;
  const Sequence s = sequence(cam, 5, rng);
  // How many queue submissions the detector's set-up and each frame make is the runtime's
  // business: lose the device after k of them, for growing k, until the loss falls after the
  // first frame's result.
  for (int k = 1; k <= 100; ++k) {
    vk::ContextOptions options = testing::test_context_options();
    options.lose_device_after_submits = k;
    Device device(options);
    Collector got;
    PipelineConfig c = config_for(cam);
    c.detector.backend = Backend::kVulkan;
    c.on_frame = [&](const FrameResult& r) { got.add(r); };
    std::optional<Pipeline> p;
    try {
      p.emplace(c, device);
    } catch (const DeviceLostError&) {
      continue;  // lost while building the stages
    }
    std::string error;
    try {
      for (const CameraFrame& f : s.frames) p->push(CameraFrame{f.timestamp_ns, f.image});
      p->finish();
    } catch (const DeviceLostError& e) {
      error = e.what();
    }
    ASSERT_FALSE(error.empty()) << "no loss after " << k << " submissions";
    if (got.results.empty()) continue;  // lost at the first frame
    ASSERT_LT(got.results.size(), s.frames.size());
    for (const FrameResult& r : got.results) EXPECT_TRUE(r.error.empty()) << r.error;
    const int64_t lost_at = s.frames[got.results.size()].timestamp_ns;
    EXPECT_NE(error.find("device was lost at the frame at t = " + std::to_string(lost_at)),
              std::string::npos)
        << error;
    EXPECT_NE(error.find("VK_ERROR_DEVICE_LOST"), std::string::npos) << error;
    EXPECT_THROW(p->finish(), DeviceLostError);
    return;
  }
  FAIL() << "the device was never lost after the first frame";
}

TEST(Pipeline, MisuseGivesClearErrors) {
  const PinholeCamera cam;
  PipelineConfig lossless = config_for(cam);
  lossless.lossless_results = true;
  try {
    Pipeline p(lossless, test_device());
    ADD_FAILURE() << "lossless results without a callback accepted";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("on_frame"), std::string::npos) << e.what();
  }
  Pipeline p(config_for(cam), test_device());
  EXPECT_THROW(p.global_pose_counters(), Error);
  p.finish();
  p.finish();
  EXPECT_THROW(p.push(CameraFrame{kT0, ImageU8(cam.width_px, cam.height_px)}), Error);
  EXPECT_THROW(p.push(PressureSample{kT0, 1.0}), Error);
}

}  // namespace
}  // namespace pensight
