#include "pipeline/depth/depth_input.h"

#include <algorithm>
#include <cstdint>
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

NetworkView network_view(int camera_width, int camera_height, int width, int height) {
  if (camera_width <= 0 || camera_height <= 0 || width <= 0 || height <= 0) {
    throw Error("network_view: sizes must be positive, got a " + std::to_string(camera_width) +
                "x" + std::to_string(camera_height) + " camera and a " + std::to_string(width) +
                "x" + std::to_string(height) + " network");
  }
  const int64_t cw = camera_width, ch = camera_height;
  NetworkView v{0, 0, camera_width, camera_height};
  if (cw * height > ch * width) {  // wider than the network: crop the sides
    v.width_px = static_cast<int>(std::clamp<int64_t>((ch * width + height / 2) / height, 1, cw));
  } else if (cw * height < ch * width) {  // taller: crop top and bottom
    v.height_px = static_cast<int>(std::clamp<int64_t>((cw * height + width / 2) / width, 1, ch));
  }
  v.x0_px = (camera_width - v.width_px) / 2;
  v.y0_px = (camera_height - v.height_px) / 2;
  return v;
}

PinholeCamera network_camera(const PinholeCamera& camera, const NetworkView& view, int width,
                             int height) {
  const double sx = static_cast<double>(width) / view.width_px;
  const double sy = static_cast<double>(height) / view.height_px;
  PinholeCamera c = camera;
  c.width_px = width;
  c.height_px = height;
  c.fx_px *= sx;
  c.fy_px *= sy;
  // Pixel centres at integers: the crop's edge (x0 - 0.5) lands on -0.5.
  c.cx_px = (camera.cx_px - view.x0_px + 0.5) * sx - 0.5;
  c.cy_px = (camera.cy_px - view.y0_px + 0.5) * sy - 0.5;
  return c;
}

ImageU8 network_image(const ImageU8& image, const NetworkView& view, int width, int height) {
  if (view.x0_px == 0 && view.y0_px == 0 && view.width_px == image.width &&
      view.height_px == image.height) {
    return resize_area(image, width, height);
  }
  ImageU8 crop(view.width_px, view.height_px);
  for (int y = 0; y < view.height_px; ++y) {
    const uint8_t* row = &image.at(view.x0_px, view.y0_px + y);
    std::copy(row, row + view.width_px, &crop.at(0, y));
  }
  return resize_area(crop, width, height);
}

std::vector<SparseDepth> network_depths(std::span<const SparseDepth> depths,
                                        const NetworkView& view, int width, int height) {
  std::vector<size_t> order;
  order.reserve(depths.size());
  for (size_t i = 0; i < depths.size(); ++i) {
    const kernels::SparsePoint& p = depths[i].point;
    const double x = double{p.x_px} - view.x0_px, y = double{p.y_px} - view.y0_px;
    if (x >= -0.5 && y >= -0.5 && x < view.width_px - 0.5 && y < view.height_px - 0.5) {
      order.push_back(i);
    }
  }
  if (order.size() > static_cast<size_t>(kernels::kMaxSparsePoints)) {
    std::stable_sort(order.begin(), order.end(),
                     [&](size_t a, size_t b) { return depths[a].quality > depths[b].quality; });
    order.resize(kernels::kMaxSparsePoints);
    std::sort(order.begin(), order.end());
  }
  const double sx = static_cast<double>(width) / view.width_px;
  const double sy = static_cast<double>(height) / view.height_px;
  std::vector<SparseDepth> out;
  out.reserve(order.size());
  for (const size_t i : order) {
    const kernels::SparsePoint& p = depths[i].point;
    out.push_back({{static_cast<float>((double{p.x_px} - view.x0_px + 0.5) * sx - 0.5),
                    static_cast<float>((double{p.y_px} - view.y0_px + 0.5) * sy - 0.5), p.depth_m},
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
