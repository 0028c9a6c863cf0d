#pragma once
// Host-side image value type shared by kernels, the simulator and the pipeline. Owns its pixels;
// rows are tightly packed (stride == width).
#include <array>
#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

namespace pensight {

// The largest image side pensight reads from a dataset or a bag (cam0/sensor.yaml's resolution,
// sensor_msgs Image and CameraInfo): far above any camera, small enough that width x height x 4
// bytes stays within 1 GiB.
inline constexpr int kMaxImageSide_px = 16384;

template <class T>
struct Image {
  int width = 0;
  int height = 0;
  std::vector<T> pixels;

  Image() = default;
  Image(int w, int h, T fill = T{})
      : width(w), height(h), pixels(static_cast<size_t>(w) * h, fill) {}

  T& at(int x, int y) { return pixels[static_cast<size_t>(y) * width + x]; }
  const T& at(int x, int y) const { return pixels[static_cast<size_t>(y) * width + x]; }
  std::span<T> span() { return pixels; }
  std::span<const T> span() const { return pixels; }
  bool empty() const { return pixels.empty(); }
};

using ImageU8 = Image<uint8_t>;
using ImageU16 = Image<uint16_t>;
using ImageF32 = Image<float>;
using ImageRgb8 = Image<std::array<uint8_t, 3>>;  // red, green, blue

}  // namespace pensight
