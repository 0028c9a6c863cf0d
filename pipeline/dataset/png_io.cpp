#include "pipeline/dataset/png_io.h"

#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include <cstdint>
#include <string>
#include <string_view>

#include "core/atomic_file.h"
#include "core/error.h"
#include "core/file_bytes.h"

namespace pensight {
namespace {

// The largest image read: 64 megapixels, 8x a 4K frame.
constexpr uint64_t kMaxImagePixels = uint64_t{1} << 26;

cv::Mat read_any(const std::filesystem::path& file, int expect_width, int expect_height) {
  if (!std::filesystem::is_regular_file(file)) {
    throw Error("image '" + file.string() + "' not found: check the file names in data.csv");
  }
  // Only PNG (dataset-format.md): OpenCV would also decode BMP, TIFF, JPEG 2000 ... and allocate
  // whatever size their headers claim. A PNG's size is in its header, so a wrong or absurd size
  // is refused before the decoder allocates what the header claims.
  std::string bytes = read_file_bytes(file).value_or("");  // cv::Mat wraps it, non-const
  constexpr std::string_view kPngSignature("\x89PNG\r\n\x1a\n", 8);
  if (bytes.size() < 24 || std::string_view(bytes).substr(0, 8) != kPngSignature) {
    throw Error("image '" + file.string() +
                "' is not a PNG file (frames and depth images are PNG, dataset-format.md)");
  }
  const auto be32 = [&](size_t at) {
    uint32_t v = 0;
    for (size_t i = 0; i < 4; ++i) v = (v << 8) | static_cast<uint8_t>(bytes[at + i]);
    return v;
  };
  const uint64_t w = be32(16), h = be32(20);
  const bool wrong_size = expect_width > 0 && (w != static_cast<uint64_t>(expect_width) ||
                                               h != static_cast<uint64_t>(expect_height));
  if (wrong_size || w * h > kMaxImagePixels || bytes.size() > kMaxImagePixels * 8) {
    throw Error("image '" + file.string() + "' is " + std::to_string(w) + "x" + std::to_string(h) +
                (wrong_size
                     ? " but sensor.yaml says " + std::to_string(expect_width) + "x" +
                           std::to_string(expect_height) + ": fix the resolution or the image"
                     : ", larger than pensight reads (64 megapixels)"));
  }
  const cv::Mat raw(1, static_cast<int>(bytes.size()), CV_8UC1, bytes.data());
  cv::Mat m = cv::imdecode(raw, cv::IMREAD_UNCHANGED);
  if (m.empty()) throw Error("cannot decode image '" + file.string() + "': not a valid PNG");
  if (expect_width > 0 && (m.cols != expect_width || m.rows != expect_height)) {
    throw Error("image '" + file.string() + "' is " + std::to_string(m.cols) + "x" +
                std::to_string(m.rows) + " but sensor.yaml says " + std::to_string(expect_width) +
                "x" + std::to_string(expect_height) + ": fix the resolution or the image");
  }
  return m;
}

template <class T>
Image<T> to_image(const cv::Mat& m) {
  Image<T> img(m.cols, m.rows);
  cv::Mat view(m.rows, m.cols, m.type(), img.pixels.data());
  m.copyTo(view);
  return img;
}

void write_mat(const std::filesystem::path& file, const cv::Mat& m) {
  std::vector<uchar> bytes;
  // Fast zlib level, run-length matching only: on rendered frames and depth maps it is ~20 %
  // faster than the default strategy and the files are smaller (docs/performance.md).
  if (!cv::imencode(".png", m, bytes,
                    {cv::IMWRITE_PNG_COMPRESSION, 1, cv::IMWRITE_PNG_STRATEGY,
                     cv::IMWRITE_PNG_STRATEGY_RLE})) {
    throw Error("cannot encode '" + file.string() + "' as PNG");
  }
  write_file_atomically(
      file, std::string_view(reinterpret_cast<const char*>(bytes.data()), bytes.size()));
}

}  // namespace

ImageU8 read_png_grey8(const std::filesystem::path& file, int expect_width, int expect_height) {
  cv::Mat m = read_any(file, expect_width, expect_height);
  if (m.channels() == 3) {
    cv::cvtColor(m, m, cv::COLOR_BGR2GRAY);
  } else if (m.channels() == 4) {
    cv::cvtColor(m, m, cv::COLOR_BGRA2GRAY);
  } else if (m.channels() != 1) {
    throw Error("image '" + file.string() + "' has " + std::to_string(m.channels()) +
                " channels; expected grey or colour");
  }
  if (m.depth() == CV_16U) {
    m.convertTo(m, CV_8U, 255.0 / 65535.0);
  } else if (m.depth() != CV_8U) {
    throw Error("image '" + file.string() + "' is neither 8- nor 16-bit");
  }
  return to_image<uint8_t>(m);
}

ImageU16 read_png_u16(const std::filesystem::path& file, int expect_width, int expect_height) {
  const cv::Mat m = read_any(file, expect_width, expect_height);
  if (m.type() != CV_16UC1) {
    throw Error("image '" + file.string() + "' must be a 16-bit single-channel PNG");
  }
  return to_image<uint16_t>(m);
}

void write_png(const std::filesystem::path& file, const ImageU8& image) {
  write_mat(file,
            cv::Mat(image.height, image.width, CV_8UC1, const_cast<uint8_t*>(image.pixels.data())));
}

void write_png(const std::filesystem::path& file, const ImageU16& image) {
  write_mat(file, cv::Mat(image.height, image.width, CV_16UC1,
                          const_cast<uint16_t*>(image.pixels.data())));
}

void write_png(const std::filesystem::path& file, const ImageRgb8& image) {
  const cv::Mat rgb(image.height, image.width, CV_8UC3,
                    const_cast<std::array<uint8_t, 3>*>(image.pixels.data()));
  cv::Mat bgr;
  cv::cvtColor(rgb, bgr, cv::COLOR_RGB2BGR);  // OpenCV writes its BGR order as RGB
  write_mat(file, bgr);
}

}  // namespace pensight
