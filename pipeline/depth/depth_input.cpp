#include "pipeline/depth/depth_input.h"

#include <algorithm>
#include <numeric>
#include <opencv2/imgproc.hpp>
#include <string>

#include "core/error.h"

namespace pensight {

ImageU8 resize_area(const ImageU8& image, int width, int height) {
  if (image.empty() || width <= 0 || height <= 0) {
    throw Error("resize_area: empty image or size " + std::to_string(width) + "x" +
                std::to_string(height));
  }
  const cv::Mat src(image.height, image.width, CV_8UC1, const_cast<uint8_t*>(image.pixels.data()));
  ImageU8 out(width, height);
  cv::Mat dst(height, width, CV_8UC1, out.pixels.data());
  cv::resize(src, dst, dst.size(), 0, 0, cv::INTER_AREA);
  return out;
}

std::vector<SparseDepth> network_depths(std::span<const SparseDepth> depths, int camera_width,
                                        int camera_height, int width, int height) {
  std::vector<size_t> order(depths.size());
  std::iota(order.begin(), order.end(), size_t{0});
  if (order.size() > static_cast<size_t>(kernels::kMaxSparsePoints)) {
    std::stable_sort(order.begin(), order.end(),
                     [&](size_t a, size_t b) { return depths[a].quality > depths[b].quality; });
    order.resize(kernels::kMaxSparsePoints);
    std::sort(order.begin(), order.end());
  }
  const double sx = static_cast<double>(width) / camera_width;
  const double sy = static_cast<double>(height) / camera_height;
  std::vector<SparseDepth> out;
  out.reserve(order.size());
  for (const size_t i : order) {
    const kernels::SparsePoint& p = depths[i].point;
    out.push_back({{static_cast<float>((p.x_px + 0.5) * sx - 0.5),
                    static_cast<float>((p.y_px + 0.5) * sy - 0.5), p.depth_m},
                   depths[i].quality});
  }
  return out;
}

std::vector<kernels::SparsePoint> points_of(std::span<const SparseDepth> depths) {
  std::vector<kernels::SparsePoint> out(depths.size());
  std::transform(depths.begin(), depths.end(), out.begin(),
                 [](const SparseDepth& d) { return d.point; });
  return out;
}

}  // namespace pensight
