#include "live/camera_source.h"

#include <opencv2/imgproc.hpp>
#include <opencv2/videoio.hpp>

#include <chrono>
#include <condition_variable>
#include <mutex>
#include <set>
#include <thread>

#include "core/error.h"
#include "core/log.h"
#include "core/timing.h"
#include "core/units.h"
#include "pipeline/dataset/dataset_reader.h"

namespace pensight::live {

const Param<CameraSourceParams> kCameraSourceParams[] = {
    {"latency_s", &CameraSourceParams::latency_s, "s", closed_range(0, 5),
     "exposure to arrival on the host, subtracted from each frame's stamp"},
    {"timeout_s", &CameraSourceParams::timeout_s, "s", closed_range(0.1, 60),
     "a stream without a frame for this long has stalled and is reopened"},
    {"reconnect_s", &CameraSourceParams::reconnect_s, "s", closed_range(0.01, 60),
     "wait between attempts to open the camera stream"},
};

std::span<const Param<CameraSourceParams>> camera_source_params() {
  return kCameraSourceParams;
}

struct CameraSource::State {
  CameraUri uri;
  PinholeCamera camera;
  CameraSourceParams params;
  std::optional<Dataset> dataset;

  mutable std::mutex mutex;
  std::condition_variable changed;
  std::optional<CameraFrame> newest;
  CameraCounters counters;
  std::string last_error;
  std::set<std::string> said;  // the faults already logged, by kind
  bool stop = false;
  bool finished = false;
  std::thread thread;
  bool thread_done = false;

  // Waits until `deadline` on the steady clock or a stop; true when stopped.
  bool sleep_until(int64_t deadline_steady_ns) {
    std::unique_lock lock(mutex);
    return changed.wait_for(
        lock, std::chrono::nanoseconds(std::max<int64_t>(0, deadline_steady_ns - steady_now_ns())),
        [&] { return stop; });
  }
  bool stopping() {
    const std::lock_guard lock(mutex);
    return stop;
  }
  // Counts with `count`, keeps the message, logs the first of each kind.
  void fault(const std::string& kind, const std::string& message, uint64_t CameraCounters::*count) {
    bool first = false;
    {
      const std::lock_guard lock(mutex);
      ++(counters.*count);
      last_error = message;
      first = said.insert(kind).second;
    }
    if (first) log_warning(message + " (said once; counted from now on)");
  }
  void publish(CameraFrame frame) {
    const std::lock_guard lock(mutex);
    ++counters.frames;
    if (newest) ++counters.dropped;
    newest = std::move(frame);
    changed.notify_all();
  }
};

namespace {

bool open_capture(cv::VideoCapture& cap, const CameraUri& uri, const CameraSourceParams& p) {
  const int timeout_ms = static_cast<int>(p.timeout_s * 1000);
  try {
    switch (uri.kind) {
      case CameraUriKind::kV4l2:
        if (uri.target.find_first_not_of("0123456789") == std::string::npos) {
          return cap.open(std::stoi(uri.target), cv::CAP_V4L2);
        }
        return cap.open(uri.target, cv::CAP_V4L2);
      case CameraUriKind::kGstreamer:
        return cap.open(uri.target, cv::CAP_GSTREAMER);
      case CameraUriKind::kNetwork:
      case CameraUriKind::kFile:
        return cap.open(uri.target, cv::CAP_FFMPEG,
                        {cv::CAP_PROP_OPEN_TIMEOUT_MSEC, timeout_ms, cv::CAP_PROP_READ_TIMEOUT_MSEC,
                         timeout_ms});
      case CameraUriKind::kDataset:
        break;
    }
  } catch (const cv::Exception&) {
    // Reported as a failure to open, like a false return.
  }
  return false;
}

// 8-bit grey, whatever the backend delivers.
cv::Mat to_grey(const cv::Mat& m) {
  cv::Mat eight = m;
  if (m.depth() == CV_16U) m.convertTo(eight, CV_8U, 1.0 / 256);
  cv::Mat grey;
  if (eight.channels() == 3) {
    cv::cvtColor(eight, grey, cv::COLOR_BGR2GRAY);
  } else if (eight.channels() == 4) {
    cv::cvtColor(eight, grey, cv::COLOR_BGRA2GRAY);
  } else {
    grey = eight;
  }
  return grey;
}

void capture_stream(CameraSource::State& s) {
  cv::VideoCapture cap;
  bool opened_before = false;
  while (!s.stopping()) {
    if (!cap.isOpened()) {
      if (!open_capture(cap, s.uri, s.params)) {
        s.fault("open",
                "camera '" + s.uri.text + "' did not open; retrying every " +
                    format_param_value(s.params.reconnect_s) +
                    " s (check the URI, the cable or the stream's sender)",
                &CameraCounters::open_failures);
        if (s.sleep_until(steady_now_ns() + seconds_to_ns(s.params.reconnect_s))) break;
        continue;
      }
      if (opened_before) {
        const std::lock_guard lock(s.mutex);
        ++s.counters.reconnects;
      }
      opened_before = true;
    }
    cv::Mat m;
    bool ok = false;
    try {
      ok = cap.read(m) && !m.empty();
    } catch (const cv::Exception&) {
      ok = false;
    }
    const int64_t arrival_ns = host_now_ns();
    if (!ok) {
      s.fault("stall",
              "camera '" + s.uri.text + "': no frame within " +
                  format_param_value(s.params.timeout_s) +
                  " s (the stream ended or stalled); reopening",
              &CameraCounters::stalls);
      cap.release();
      continue;
    }
    const cv::Mat grey = to_grey(m);
    if (grey.cols != s.camera.width_px || grey.rows != s.camera.height_px) {
      s.fault("size",
              "camera '" + s.uri.text + "': frame of " + std::to_string(grey.cols) + "x" +
                  std::to_string(grey.rows) + " px, the calibration's is " +
                  std::to_string(s.camera.width_px) + "x" + std::to_string(s.camera.height_px) +
                  "; frame skipped (set the camera's mode or the calibration to match)",
              &CameraCounters::wrong_size);
      continue;
    }
    CameraFrame f;
    f.timestamp_ns = arrival_ns - seconds_to_ns(s.params.latency_s);
    f.image = ImageU8(grey.cols, grey.rows);
    for (int y = 0; y < grey.rows; ++y) {
      const uint8_t* row = grey.ptr<uint8_t>(y);
      std::copy(row, row + grey.cols,
                f.image.pixels.begin() + static_cast<ptrdiff_t>(y) * grey.cols);
    }
    s.publish(std::move(f));
  }
}

// The dataset's frames at their own pace, stamped on the host clock from the first one's play.
void play_dataset(CameraSource::State& s) {
  const Dataset& d = *s.dataset;
  const int64_t host_start_ns = host_now_ns();
  const int64_t steady_start_ns = steady_now_ns();
  const int64_t t0 = d.frames.front().timestamp_ns;
  for (size_t i = 0; i < d.frames.size(); ++i) {
    const int64_t offset_ns = d.frames[i].timestamp_ns - t0;
    if (s.sleep_until(steady_start_ns + offset_ns)) return;
    CameraFrame f;
    f.timestamp_ns = host_start_ns + offset_ns - seconds_to_ns(s.params.latency_s);
    try {
      f.image = d.load_frame(i);
    } catch (const Error& e) {
      s.fault("frame", "camera '" + s.uri.text + "': " + e.what() + "; frame skipped",
              &CameraCounters::stalls);
      continue;
    }
    s.publish(std::move(f));
  }
  const std::lock_guard lock(s.mutex);
  s.finished = true;
  s.changed.notify_all();
}

}  // namespace

CameraSource::CameraSource(CameraUri uri, const PinholeCamera& camera, CameraSourceParams params)
    : state_(std::make_shared<State>()) {
  check_params<CameraSourceParams>(params, camera_source_params(), "camera", "camera.");
  state_->uri = std::move(uri);
  state_->camera = camera;
  state_->params = params;
  if (state_->uri.kind == CameraUriKind::kDataset) {
    state_->dataset = read_dataset(state_->uri.target);
    const PinholeCamera& c = state_->dataset->cam0.camera;
    check_image_size(c.width_px, c.height_px, camera,
                     ("camera '" + state_->uri.text + "'").c_str());
  }
  state_->thread = std::thread([s = state_] {
    if (s->dataset) {
      play_dataset(*s);
    } else {
      capture_stream(*s);
    }
    const std::lock_guard lock(s->mutex);
    s->thread_done = true;
    s->changed.notify_all();
  });
}

CameraSource::~CameraSource() {
  std::unique_lock lock(state_->mutex);
  state_->stop = true;
  state_->changed.notify_all();
  // A read has its own timeout on FFmpeg; V4L2 and GStreamer reads may not: the thread (which
  // holds the state) is then left to end on its own.
  const bool done = state_->changed.wait_for(
      lock, std::chrono::nanoseconds(seconds_to_ns(state_->params.timeout_s + 1.0)),
      [&] { return state_->thread_done; });
  lock.unlock();
  if (done) {
    state_->thread.join();
  } else {
    state_->thread.detach();
  }
}

std::optional<CameraFrame> CameraSource::take(double timeout_s) {
  std::unique_lock lock(state_->mutex);
  state_->changed.wait_for(lock, std::chrono::nanoseconds(seconds_to_ns(timeout_s)),
                           [&] { return state_->newest.has_value() || state_->finished; });
  if (!state_->newest) return std::nullopt;
  std::optional<CameraFrame> out = std::move(state_->newest);
  state_->newest.reset();
  ++state_->counters.taken;
  return out;
}

CameraCounters CameraSource::counters() const {
  const std::lock_guard lock(state_->mutex);
  return state_->counters;
}

std::string CameraSource::last_error() const {
  const std::lock_guard lock(state_->mutex);
  return state_->last_error;
}

bool CameraSource::finished() const {
  const std::lock_guard lock(state_->mutex);
  return state_->finished && !state_->newest;
}

}  // namespace pensight::live
