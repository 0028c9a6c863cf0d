#pragma once
// A live camera as a source of grey frames stamped on the host clock (system_clock, ns since the
// Unix epoch): a capture thread reads the stream (OpenCV's VideoCapture: V4L2, GStreamer or
// FFmpeg by the URI, camera_uri.h; or a dataset's frames played at their time stamps) and keeps
// only the newest frame, so a slow consumer never blocks the camera: a frame it did not take in
// time is dropped and counted. A frame is stamped at its arrival minus the configured latency
// (exposure to arrival: an H.264 stream from BlueOS is about 0.1-0.2 s behind), colour converted
// to grey, and skipped (counted) when its size is not the calibration's. A stream that fails to
// open, ends or stalls is reopened every reconnect_s; faults are counted and said once each in
// last_error(), never thrown after construction.
#include <cstdint>
#include <memory>
#include <optional>
#include <span>
#include <string>

#include "core/camera.h"
#include "core/image.h"
#include "core/params.h"
#include "live/camera_uri.h"

namespace pensight::live {

struct CameraSourceParams {
  double latency_s = 0.0;    // exposure to arrival on the host, subtracted from each stamp
  double timeout_s = 2.0;    // a stream without a frame for this long has stalled: reopened
  double reconnect_s = 1.0;  // between attempts to open the stream
};

// Key, unit, valid range and help of every CameraSourceParams member (the `camera:` section).
std::span<const Param<CameraSourceParams>> camera_source_params();

struct CameraFrame {
  int64_t timestamp_ns = 0;  // host clock, exposure time
  ImageU8 image;
};

struct CameraCounters {
  uint64_t frames = 0;      // read from the stream with the calibration's size
  uint64_t taken = 0;       // handed to the consumer
  uint64_t dropped = 0;     // replaced by a newer frame before the consumer took them
  uint64_t wrong_size = 0;  // not the calibration's size: skipped
  uint64_t stalls = 0;      // reads that failed, timed out or hit the end of the stream
  uint64_t reconnects = 0;  // opens after the first
  uint64_t open_failures = 0;
};

class CameraSource {
 public:
  // Starts the capture thread. `camera` gives the frame size every frame must have. Throws
  // pensight::Error naming the URI or key for bad parameters, and for a dataset: URI whose
  // dataset cannot be read or whose frames are not camera's size; a live stream that does not
  // open is retried, not thrown.
  CameraSource(CameraUri uri, const PinholeCamera& camera, CameraSourceParams params = {});
  // Stops the capture thread (a backend blocked in a read without a timeout is left to finish on
  // its own within the process).
  ~CameraSource();
  CameraSource(const CameraSource&) = delete;
  CameraSource& operator=(const CameraSource&) = delete;

  // The newest frame not yet taken, waiting up to timeout_s for one; nullopt when none came.
  std::optional<CameraFrame> take(double timeout_s);
  CameraCounters counters() const;
  std::string last_error() const;
  // A dataset: source after its last frame; a live stream never ends (it is reopened).
  bool finished() const;

  struct State;

 private:
  std::shared_ptr<State> state_;
};

}  // namespace pensight::live
