#include "live/camera_uri.h"

#include <array>
#include <string_view>

#include "core/error.h"

namespace pensight::live {
namespace {

constexpr std::string_view kForms =
    "v4l2:/dev/videoN, gst:<pipeline ending in appsink>, rtsp:// rtp:// udp:// tcp:// http(s):// "
    "URL, dataset:DIR, file:PATH or a file path";

bool starts_with(std::string_view s, std::string_view prefix) {
  return s.substr(0, prefix.size()) == prefix;
}

[[noreturn]] void fail(const std::string& uri, const std::string& why) {
  throw Error("camera uri '" + uri + "': " + why + " (accepted: " + std::string(kForms) + ")");
}

}  // namespace

CameraUri parse_camera_uri(const std::string& uri) {
  CameraUri out;
  out.text = uri;
  if (uri.find_first_not_of(" \t") == std::string::npos) fail(uri, "empty");
  constexpr std::array<std::string_view, 7> kNetworkSchemes = {
      "rtsp://", "rtsps://", "rtp://", "udp://", "tcp://", "http://", "https://"};
  for (const std::string_view scheme : kNetworkSchemes) {
    if (starts_with(uri, scheme)) {
      if (uri.size() == scheme.size()) fail(uri, "no address after " + std::string(scheme));
      out.kind = CameraUriKind::kNetwork;
      out.target = uri;
      return out;
    }
  }
  const size_t colon = uri.find(':');
  const std::string scheme = colon == std::string::npos ? "" : uri.substr(0, colon);
  const std::string rest = colon == std::string::npos ? uri : uri.substr(colon + 1);
  if (scheme == "v4l2") {
    out.kind = CameraUriKind::kV4l2;
  } else if (scheme == "gst") {
    out.kind = CameraUriKind::kGstreamer;
    if (rest.find("appsink") == std::string::npos) {
      fail(uri,
           "the GStreamer pipeline must end in appsink, e.g. '... ! videoconvert ! "
           "video/x-raw,format=GRAY8 ! appsink sync=false max-buffers=1 drop=true'");
    }
  } else if (scheme == "dataset") {
    out.kind = CameraUriKind::kDataset;
  } else if (scheme == "file" || scheme.empty() || scheme.find('/') != std::string::npos) {
    out.kind = CameraUriKind::kFile;
    if (scheme != "file") {
      out.target = uri;  // a plain path (that may hold a ':')
      return out;
    }
  } else {
    fail(uri, "unknown scheme '" + scheme + ":'");
  }
  if (rest.find_first_not_of(" \t") == std::string::npos)
    fail(uri, "nothing after '" + scheme + ":'");
  out.target = rest;
  return out;
}

}  // namespace pensight::live
