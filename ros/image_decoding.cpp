#include "ros/image_decoding.h"

#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include <optional>
#include <string_view>
#include <utility>

#include "core/error.h"
#include "core/image.h"

namespace pensight {
namespace {

ImageU8 to_image(const cv::Mat& grey) {
  ImageU8 img(grey.cols, grey.rows);
  grey.copyTo(cv::Mat(grey.rows, grey.cols, CV_8UC1, img.pixels.data()));
  return img;
}

uint32_t be16(std::span<const uint8_t> d, size_t at) {
  return (uint32_t{d[at]} << 8) | d[at + 1];
}

uint32_t be32(std::span<const uint8_t> d, size_t at) {
  return (be16(d, at) << 16) | be16(d, at + 2);
}

// Width and height from a JPEG's frame header (SOFn), or nullopt when there is none before the
// scan data.
std::optional<std::pair<uint32_t, uint32_t>> jpeg_size(std::span<const uint8_t> d) {
  size_t at = 2;  // after SOI
  while (at + 4 <= d.size()) {
    if (d[at] != 0xFF) return std::nullopt;
    const uint8_t marker = d[at + 1];
    if (marker == 0xFF) {  // fill byte
      ++at;
      continue;
    }
    if (marker == 0x01 || (marker >= 0xD0 && marker <= 0xD8)) {  // no length field
      at += 2;
      continue;
    }
    const uint32_t length = be16(d, at + 2);
    const bool frame_header =
        marker >= 0xC0 && marker <= 0xCF && marker != 0xC4 && marker != 0xC8 && marker != 0xCC;
    if (frame_header) {
      if (at + 9 > d.size()) return std::nullopt;
      return std::pair{be16(d, at + 7), be16(d, at + 5)};
    }
    if (marker == 0xDA || length < 2) return std::nullopt;  // scan data before any frame header
    at += 2 + length;
  }
  return std::nullopt;
}

}  // namespace

const char* const kSupportedImageEncodings = "mono8, bgr8, rgb8";

ImageU8 grey_from_raw_image(uint32_t width, uint32_t height, uint32_t step,
                            const std::string& encoding, std::span<const uint8_t> data,
                            const std::string& topic) {
  int channels = 0, to_grey = 0;
  if (encoding == "mono8") {
    channels = 1;
  } else if (encoding == "bgr8") {
    channels = 3, to_grey = cv::COLOR_BGR2GRAY;
  } else if (encoding == "rgb8") {
    channels = 3, to_grey = cv::COLOR_RGB2GRAY;
  } else {
    throw Error("topic '" + topic + "': image encoding '" + encoding +
                "' is not supported; pensight reads " + kSupportedImageEncodings +
                " (convert the images in the bag, or publish one of these)");
  }
  constexpr auto kMaxSide = static_cast<uint32_t>(kMaxImageSide_px);
  if (width == 0 || height == 0 || width > kMaxSide || height > kMaxSide) {
    throw Error("topic '" + topic + "': image of " + std::to_string(width) + "x" +
                std::to_string(height) + " px; pensight reads 1 to " + std::to_string(kMaxSide) +
                " px per side");
  }
  if (uint64_t{step} < uint64_t{width} * channels ||
      data.size() < uint64_t{height} * uint64_t{step}) {
    throw Error("topic '" + topic + "': a " + encoding + " image of " + std::to_string(width) +
                "x" + std::to_string(height) + " px needs a step of at least " +
                std::to_string(uint64_t{width} * channels) + " bytes and height * step bytes; it " +
                "has a step of " + std::to_string(step) + " and " + std::to_string(data.size()) +
                " bytes (a damaged message)");
  }
  const cv::Mat view(static_cast<int>(height), static_cast<int>(width), CV_8UC(channels),
                     const_cast<uint8_t*>(data.data()), step);
  if (channels == 1) return to_image(view);
  cv::Mat grey;
  cv::cvtColor(view, grey, to_grey);
  return to_image(grey);
}

ImageU8 grey_from_compressed_image(const std::string& format, std::span<const uint8_t> data,
                                   int expect_width, int expect_height, const std::string& topic) {
  const bool says_png = format.find("png") != std::string::npos;
  const bool says_jpeg = format.find("jpeg") != std::string::npos;
  if (!says_png && !says_jpeg) {
    throw Error("topic '" + topic + "': compressed image format '" + format +
                "' is not supported; pensight reads jpeg and png (image_transport's compressed "
                "formats)");
  }
  constexpr std::string_view kPngSignature("\x89PNG\r\n\x1a\n", 8);
  const std::string_view head(reinterpret_cast<const char*>(data.data()),
                              std::min<size_t>(data.size(), 8));
  std::optional<std::pair<uint32_t, uint32_t>> size;
  if (data.size() >= 24 && head == kPngSignature) {
    size = std::pair{be32(data, 16), be32(data, 20)};
  } else if (data.size() >= 4 && data[0] == 0xFF && data[1] == 0xD8) {
    size = jpeg_size(data);
  }
  if (!size) {
    throw Error("topic '" + topic + "': a compressed image (format '" + format +
                "') whose data is not a readable JPEG or PNG (a damaged message)");
  }
  check_image_size(size->first, size->second, expect_width, expect_height, "topic '" + topic + "'",
                   "image", " (camera_info or --camera): give the calibration of this camera");
  const cv::Mat raw(1, static_cast<int>(data.size()), CV_8UC1, const_cast<uint8_t*>(data.data()));
  cv::Mat m = cv::imdecode(raw, cv::IMREAD_UNCHANGED);
  if (m.empty() || m.cols != expect_width || m.rows != expect_height) {
    throw Error("topic '" + topic + "': cannot decode a compressed image (format '" + format +
                "'): a damaged message");
  }
  if (m.channels() == 3) {
    cv::cvtColor(m, m, cv::COLOR_BGR2GRAY);
  } else if (m.channels() == 4) {
    cv::cvtColor(m, m, cv::COLOR_BGRA2GRAY);
  }
  if (m.depth() == CV_16U) m.convertTo(m, CV_8U, 255.0 / 65535.0);
  if (m.type() != CV_8UC1) {
    throw Error("topic '" + topic +
                "': a compressed image that is neither 8- nor 16-bit grey or "
                "colour");
  }
  return to_image(m);
}

}  // namespace pensight
