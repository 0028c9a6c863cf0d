#pragma once
// Where a live camera's frames come from, as a user writes it in the record / vehicle YAML:
//   v4l2:/dev/video0  (or v4l2:0)      a USB or CSI camera through Video4Linux2
//   gst:PIPELINE                       a GStreamer pipeline ending in appsink (BlueOS's RTP/H.264
//                                      stream on UDP 5600, see docs/vehicle.md)
//   rtsp://... rtp://... udp://... tcp://... http://... https://...
//                                      a network stream, opened by FFmpeg
//   dataset:DIR                        a dataset's frames played at their time stamps (tests,
//                                      dry runs)
//   file:PATH or PATH                  a video file, or an image sequence FFmpeg reads
#include <string>

namespace pensight::live {

enum class CameraUriKind { kV4l2, kGstreamer, kNetwork, kFile, kDataset };

struct CameraUri {
  CameraUriKind kind = CameraUriKind::kFile;
  std::string target;  // the device, pipeline, URL, file or folder, without the scheme
  std::string text;    // the URI as written, for messages
};

// Throws pensight::Error naming the URI and the accepted forms when it is empty, names an unknown
// scheme, or a gst: pipeline has no appsink.
CameraUri parse_camera_uri(const std::string& uri);

}  // namespace pensight::live
