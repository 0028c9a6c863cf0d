#include "pipeline/pipeline.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdlib>
#include <map>
#include <mutex>
#include <thread>
#include <type_traits>

#include "core/error.h"
#include "core/log.h"
#include "core/timing.h"
#include "pipeline/bounded_queue.h"

namespace pensight {
namespace {

using Clock = StageMeter::Clock;

// A DVL plane older than two DVL periods (4 Hz) no longer describes the frame.
constexpr int64_t kMaxPlaneAge_ns = 500'000'000;
// Sensor samples held per sensor for the next frame: 50 s of 200 Hz attitude.
constexpr size_t kMaxHeld = 10'000;

// A detected frame on its way to the global-pose worker.
struct Detected {
  FrameResult result;
  Clock::time_point pushed;
};
// One input of the global-pose worker: a detected frame or one sensor sample. (A tagged struct:
// GCC 12 reports a false -Wmaybe-uninitialized on moving a std::variant of these.)
struct PoseInput {
  enum Kind { kFrame, kDvl, kDepth, kAttitude } kind;
  std::unique_ptr<Detected> frame;
  DvlSample dvl;
  PressureSample depth;
  AttitudeSample attitude;
};

struct Delivered {
  FrameResult result;
  Clock::time_point pushed;
};

// Sensor samples newer than the frame being worked on, per sensor in timestamp order (equal
// timestamps in arrival order).
template <class Sample>
using Held = std::multimap<int64_t, Sample>;

// When a sensor's next sample is due, from its stamps so far (period: a running average of the
// intervals, 1/8 weight for the newest).
struct SensorClock {
  int64_t last_ns = INT64_MIN;
  int64_t period_ns = 0;

  void add(int64_t t_ns) {
    if (last_ns != INT64_MIN && t_ns > last_ns) {
      const int64_t interval = t_ns - last_ns;
      period_ns = period_ns == 0 ? interval : period_ns + (interval - period_ns) / 8;
    }
    last_ns = std::max(last_ns, t_ns);
  }
  // A sample stamped by t_ns, give or take the stamps' jitter (a quarter period, at most 5 ms: a
  // slow sensor's next sample just after the frame is not waited for), has not arrived yet.
  bool due_by(int64_t t_ns) const {
    constexpr int64_t kMaxJitter_ns = 5'000'000;
    return period_ns > 0 && last_ns + period_ns <= t_ns + std::min(period_ns / 4, kMaxJitter_ns);
  }
};

}  // namespace

global_pose::NetObservation net_observation(const NetDetection& d) {
  global_pose::NetObservation obs;
  obs.t_ns = d.timestamp_ns;
  for (const RoiNetPoint& p : d.points) {
    obs.points_C.push_back(p.valid() ? p.p_C : Eigen::Vector3d::Constant(kNaN));
    obs.quality.push_back(p.valid() ? std::max(p.quality, 1e-6) : 1.0);
  }
  if (d.pose.valid()) {
    obs.d_net_m = d.pose.d_net_m;
    obs.psi_net_rad = d.pose.psi_net_rad;
    obs.pose_quality = d.pose.quality;
  }
  obs.texture = d.texture;
  return obs;
}

struct Pipeline::Impl {
  PipelineConfig config;
  NetDetector detector;
  std::optional<DepthEstimator> depth;
  std::optional<DvlDepthCorrection> dvl_correction;  // owned by the global-pose worker
  global_pose::GlobalPoseEstimator estimator;
  std::optional<global_pose::PublishedGlobalPose> published;

  struct Pushed {
    int64_t timestamp_ns;
    std::shared_ptr<const ImageU8> image;
    std::shared_ptr<const ImageF32> depth_m;
    Clock::time_point at;
  };
  BoundedQueue<Pushed> camera_q;
  BoundedQueue<std::unique_ptr<Detected>> depth_q;
  // Sensors are fast to apply, so their queue is deep: a push() waits only when the caller is
  // far ahead of a lossless result consumer.
  BoundedQueue<PoseInput> pose_q{4096, QueuePolicy::kBlock};
  BoundedQueue<Delivered> result_q;

  // Owned by the global-pose worker.
  Held<DvlSample> held_dvl;
  Held<PressureSample> held_depth;
  Held<AttitudeSample> held_attitude;
  SensorClock dvl_clock, depth_clock, attitude_clock;
  std::optional<PoseInput> next_frame;  // a frame that came while waiting for samples

  mutable std::mutex stats_mutex;
  StageMeter fft{"fft net detection"}, relative{"relative pose (fft)"}, dense{"dense depth"},
      relative_depth{"relative pose (depth)"}, global{"global pose"}, delivery{"delivery"};

  mutable std::mutex finish_mutex;
  std::atomic<bool> finished{false};
  // Set once by the detection worker when the device is lost; push() and finish() throw it.
  std::atomic<bool> device_lost{false};
  std::string device_lost_message;  // written before device_lost is set, read after

  void throw_if_device_lost() const {
    if (device_lost) throw DeviceLostError(device_lost_message);
  }
  std::thread detect_thread, depth_thread, pose_thread, deliver_thread;

  Impl(PipelineConfig c, Device& device)
      : config(std::move(c)),
        detector(config.camera, config.detector, device),
        estimator(config.global_pose),
        camera_q(config.camera_queue, QueuePolicy::kBlock),
        depth_q(config.camera_queue, QueuePolicy::kBlock),
        result_q(config.result_queue,
                 config.lossless_results ? QueuePolicy::kBlock : QueuePolicy::kDropOldest) {
    if (config.lossless_results && !config.on_frame) {
      throw Error(
          "Pipeline: lossless_results needs an on_frame callback (nothing would drain "
          "the results); set on_frame or turn lossless_results off");
    }
    if (config.published) published.emplace(*config.published);
    if (config.depth) depth.emplace(config.camera, *config.depth, device);
    if (config.depth && (config.dvl_depth_scale || config.dvl_net_tilt) &&
        config.global_pose.dvl_beams) {
      dvl_correction.emplace(config.camera, config.global_pose.T_body_camera,
                             *config.global_pose.dvl_beams, config.dvl_depth_scale,
                             config.dvl_net_tilt);
    }
  }

  void lose_device(int64_t t_ns, const char* what) {
    device_lost_message =
        "Pipeline: the device was lost at the frame at t = " + std::to_string(t_ns) +
        " ns, and the run stops there: " + what;
    device_lost = true;
    log_error(device_lost_message);
  }

  void detect_loop() {
    while (auto item = camera_q.pop()) {
      if (device_lost) continue;  // the run is over; frames still queued get no result
      auto d = std::make_unique<Detected>();
      d->pushed = item->at;
      d->result.timestamp_ns = item->timestamp_ns;
      d->result.image = item->image;
      d->result.depth_m = item->depth_m;
      try {
        d->result.detection = detector.detect(*item->image, item->timestamp_ns);
        std::lock_guard lock(stats_mutex);
        fft.add(d->result.detection.fft_ms, d->pushed);
        relative.add(d->result.detection.pose_ms, d->pushed);
      } catch (const DeviceLostError& e) {
        lose_device(item->timestamp_ns, e.what());
        continue;
      } catch (const std::exception& e) {
        d->result.error = e.what();
      }
      if (depth) {
        depth_q.push(std::move(d));
      } else {
        pose_q.push({.kind = PoseInput::kFrame, .frame = std::move(d)});
      }
    }
    if (depth) {
      depth_q.close();
    } else {
      pose_q.close();
    }
  }

  // A frame without detection (its error set) passes through; a frame whose depth fails keeps
  // its other results, the reason in depth_pose.
  void depth_loop() {
    while (auto item = depth_q.pop()) {
      if (device_lost) continue;
      Detected& d = **item;
      FrameResult& r = d.result;
      if (r.error.empty()) {
        try {
          DenseDepth dense_depth = depth->estimate(*r.image, r.detection.depths);
          r.depth_pose = std::move(dense_depth.pose);
          r.depth_ms = dense_depth.network_ms;
          if (dense_depth.reason.empty()) {
            r.dense_depth_m = std::make_shared<const ImageF32>(std::move(dense_depth.depth_m));
            std::lock_guard lock(stats_mutex);
            dense.add(dense_depth.network_ms, d.pushed);
            relative_depth.add(dense_depth.pose_ms, d.pushed);
          }
        } catch (const DeviceLostError& e) {
          lose_device(r.timestamp_ns, e.what());
          continue;
        } catch (const std::exception& e) {
          r.depth_pose.reason = std::string("dense depth: ") + e.what();
        }
      }
      pose_q.push({.kind = PoseInput::kFrame, .frame = std::move(*item)});
    }
    pose_q.close();
  }

  template <class Sample>
  void feed_until(Held<Sample>& held, int64_t t_ns) {
    auto end = held.upper_bound(t_ns);
    for (auto it = held.begin(); it != end; ++it) {
      estimator.add(it->second);
      if (published) published->add(it->second);
      if constexpr (std::is_same_v<Sample, DvlSample>) {
        if (dvl_correction) dvl_correction->add(it->second);
      }
    }
    held.erase(held.begin(), end);
  }

  void feed_until(int64_t t_ns) {
    feed_until(held_dvl, t_ns);
    feed_until(held_depth, t_ns);
    feed_until(held_attitude, t_ns);
  }

  // Without camera frames (a stopped camera driver) the held samples would grow without bound:
  // beyond kMaxHeld per sensor the oldest go to the estimators without waiting for a frame.
  template <class Sample>
  void hold(Held<Sample>& held, const Sample& s) {
    held.emplace(s.timestamp_ns, s);
    if (held.size() > kMaxHeld) feed_until(held, held.begin()->first);
  }

  void apply_dvl_correction(FrameResult& r) {
    DvlDepthCorrected c = dvl_correction->apply(r.timestamp_ns, *r.dense_depth_m, r.depth_pose);
    r.depth_scale = c.scale;
    r.depth_tilt = c.tilt;
    if (c.depth_m) r.dense_depth_m = std::make_shared<const ImageF32>(std::move(*c.depth_m));
  }

  void process(Detected& d) {
    Stopwatch sw;
    FrameResult& r = d.result;
    if (r.error.empty()) {
      try {
        feed_until(r.timestamp_ns);
        if (dvl_correction && r.dense_depth_m) apply_dvl_correction(r);
        const global_pose::NetObservation obs = net_observation(r.detection);
        estimator.add(obs);
        r.global_pose = estimator.estimate(r.timestamp_ns);
        if (published) r.published = published->add(obs);
        if (const auto plane = estimator.last_dvl_plane();
            plane && std::abs(r.timestamp_ns - plane->first) <= kMaxPlaneAge_ns) {
          r.dvl_plane = plane->second.in_camera(config.global_pose.T_body_camera);
        }
      } catch (const std::exception& e) {
        r.error = std::string("global pose: ") + e.what();
      }
    }
    r.counters = estimator.counters();
    r.global_pose_ms = sw.elapsed_ms();
    {
      std::lock_guard lock(stats_mutex);
      if (r.error.empty()) global.add(r.global_pose_ms, d.pushed);
    }
    result_q.push({std::move(r), d.pushed});
  }

  void take_sample(const PoseInput& item) {
    switch (item.kind) {
      case PoseInput::kFrame:
        break;
      case PoseInput::kDvl:
        dvl_clock.add(item.dvl.timestamp_ns);
        hold(held_dvl, item.dvl);
        break;
      case PoseInput::kDepth:
        depth_clock.add(item.depth.timestamp_ns);
        hold(held_depth, item.depth);
        break;
      case PoseInput::kAttitude:
        attitude_clock.add(item.attitude.timestamp_ns);
        hold(held_attitude, item.attitude);
        break;
    }
  }

  // PipelineConfig::sensor_wait_ms: takes samples until none is due by the frame's time or the
  // wait is over; a frame that comes meanwhile is kept for next.
  void wait_for_due_samples(const Detected& d) {
    const int64_t t = d.result.timestamp_ns;
    const auto deadline =
        d.pushed + std::chrono::duration_cast<Clock::duration>(
                       std::chrono::duration<double, std::milli>(config.sensor_wait_ms));
    const auto due = [&] {
      return dvl_clock.due_by(t) || depth_clock.due_by(t) || attitude_clock.due_by(t);
    };
    while (due()) {
      std::optional<PoseInput> item = pose_q.pop_until(deadline);
      if (!item) return;
      if (item->kind == PoseInput::kFrame) {
        next_frame = std::move(item);
        return;
      }
      take_sample(*item);
    }
  }

  std::optional<PoseInput> next_input() {
    if (!next_frame) return pose_q.pop();
    std::optional<PoseInput> item = std::move(next_frame);
    next_frame.reset();
    return item;
  }

  void pose_loop() {
    while (auto item = next_input()) {
      if (item->kind != PoseInput::kFrame) {
        take_sample(*item);
        continue;
      }
      if (config.sensor_wait_ms > 0) wait_for_due_samples(*item->frame);
      process(*item->frame);
    }
    // Accepted samples after the last frame still reach the estimators (and their counters).
    feed_until(std::numeric_limits<int64_t>::max());
    result_q.close();
  }

  void deliver_loop() {
    while (auto item = result_q.pop()) {
      Stopwatch sw;
      try {
        config.on_frame(item->result);
      } catch (const std::exception& e) {
        // The caller's error; it must not end the delivery of later results.
        log_warning("Pipeline: on_frame threw for the frame at t = " +
                    std::to_string(item->result.timestamp_ns) + " ns: " + e.what());
      }
      std::lock_guard lock(stats_mutex);
      delivery.add(sw.elapsed_ms(), item->pushed);
    }
  }

  // finish() without the device-lost report (the destructor must not throw).
  void stop() {
    std::lock_guard lock(finish_mutex);
    if (finished.exchange(true)) return;
    camera_q.close();
    detect_thread.join();  // closes the depth queue (or, without it, the pose queue) when drained
    if (depth_thread.joinable()) depth_thread.join();  // closes the pose queue when drained
    pose_thread.join();                                // closes the result queue when drained
    if (deliver_thread.joinable()) deliver_thread.join();
  }

  void push_sensor(PoseInput input) {
    if (finished || !pose_q.push(std::move(input))) {
      throw Error("Pipeline: sensor sample pushed after finish(); push before finishing");
    }
  }
};

Pipeline::Pipeline(PipelineConfig config, Device& device)
    : impl_(std::make_unique<Impl>(std::move(config), device)) {
  Impl& m = *impl_;
  m.detect_thread = std::thread([&m] { m.detect_loop(); });
  if (m.depth) m.depth_thread = std::thread([&m] { m.depth_loop(); });
  m.pose_thread = std::thread([&m] { m.pose_loop(); });
  if (m.config.on_frame) m.deliver_thread = std::thread([&m] { m.deliver_loop(); });
}

Pipeline::~Pipeline() {
  impl_->stop();
}

void Pipeline::push(CameraFrame frame) {
  Impl& m = *impl_;
  m.throw_if_device_lost();
  auto image = std::make_shared<const ImageU8>(std::move(frame.image));
  if (m.finished || !m.camera_q.push({frame.timestamp_ns, std::move(image),
                                      std::move(frame.depth_m), Clock::now()})) {
    throw Error("Pipeline: camera frame pushed after finish(); push before finishing");
  }
}
void Pipeline::push(const DvlSample& s) {
  impl_->push_sensor({.kind = PoseInput::kDvl, .dvl = s});
}
void Pipeline::push(const PressureSample& s) {
  impl_->push_sensor({.kind = PoseInput::kDepth, .depth = s});
}
void Pipeline::push(const AttitudeSample& s) {
  impl_->push_sensor({.kind = PoseInput::kAttitude, .attitude = s});
}

std::optional<FrameResult> Pipeline::poll() {
  if (impl_->config.on_frame) return std::nullopt;
  auto item = impl_->result_q.try_pop();
  if (!item) return std::nullopt;
  return std::move(item->result);
}

void Pipeline::finish() {
  impl_->stop();
  impl_->throw_if_device_lost();
}

std::vector<StageStats> Pipeline::stats() const {
  const Impl& m = *impl_;
  std::lock_guard lock(m.stats_mutex);
  std::vector<StageStats> out = {m.fft.stats(), m.relative.stats()};
  if (m.depth) {
    out.push_back(m.dense.stats());
    out.push_back(m.relative_depth.stats());
  }
  out.push_back(m.global.stats());
  out.push_back(m.delivery.stats(m.result_q.dropped()));
  return out;
}

global_pose::GlobalPoseCounters Pipeline::global_pose_counters() const {
  // finish() sets the flag before joining, so hold its lock: then the workers are gone.
  std::lock_guard lock(impl_->finish_mutex);
  if (!impl_->finished) {
    throw Error("Pipeline::global_pose_counters: call finish() first (the estimator is running)");
  }
  return impl_->estimator.counters();
}

std::string Pipeline::backend_description() const {
  return impl_->detector.description();
}

std::string Pipeline::depth_description() const {
  return impl_->depth ? impl_->depth->description() : std::string();
}

}  // namespace pensight
