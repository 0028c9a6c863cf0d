#include "core/camera.h"

#include <cmath>
#include <string>

#include "core/error.h"

namespace pensight {

Eigen::Vector2d PinholeCamera::distort(const Eigen::Vector2d& xn) const {
  const double x = xn.x(), y = xn.y();
  const double r2 = x * x + y * y;
  const double radial = 1 + k1 * r2 + k2 * r2 * r2;
  return {x * radial + 2 * p1 * x * y + p2 * (r2 + 2 * x * x),
          y * radial + p1 * (r2 + 2 * y * y) + 2 * p2 * x * y};
}

Eigen::Vector2d PinholeCamera::undistort(const Eigen::Vector2d& xd) const {
  if (!has_distortion()) return xd;
  Eigen::Vector2d xn = xd;
  // Fixed point xn = xd - (distort(xn) - xn); converges quickly for the mild distortion of
  // underwater housings. 20 iterations leave < 1e-12 for |k1| < 0.5 inside the image.
  for (int i = 0; i < 20; ++i) xn = xd - (distort(xn) - xn);
  return xn;
}

std::optional<Eigen::Vector2d> PinholeCamera::project(const Eigen::Vector3d& p_C) const {
  if (!(p_C.z() > 0)) return std::nullopt;
  const Eigen::Vector2d xd = distort(p_C.head<2>() / p_C.z());
  return Eigen::Vector2d(fx_px * xd.x() + cx_px, fy_px * xd.y() + cy_px);
}

Eigen::Vector3d PinholeCamera::ray(const Eigen::Vector2d& px) const {
  const Eigen::Vector2d xn = undistort({(px.x() - cx_px) / fx_px, (px.y() - cy_px) / fy_px});
  return {xn.x(), xn.y(), 1.0};
}

PinholeCamera PinholeCamera::scaled(double scale) const {
  PinholeCamera c = *this;
  c.width_px = static_cast<int>(std::lround(width_px * scale));
  c.height_px = static_cast<int>(std::lround(height_px * scale));
  c.fx_px *= scale;
  c.fy_px *= scale;
  // Pixel centres at integers: the image edge (-0.5) stays at -0.5 after scaling.
  c.cx_px = (cx_px + 0.5) * scale - 0.5;
  c.cy_px = (cy_px + 0.5) * scale - 0.5;
  return c;
}

PinholeCamera default_field_of_view(int width_px, int height_px) {
  PinholeCamera c;
  c.width_px = width_px;
  c.height_px = height_px;
  c.fx_px = c.fy_px = kDefaultFocalLength_px * width_px / kDefaultImageWidth_px;
  c.cx_px = (width_px - 1) / 2.0;
  c.cy_px = (height_px - 1) / 2.0;
  return c;
}

void check_image_size(int64_t width_px, int64_t height_px, int camera_width_px,
                      int camera_height_px, std::string_view what, std::string_view image,
                      std::string_view fix) {
  if (width_px == camera_width_px && height_px == camera_height_px) return;
  throw Error(std::string(what) + ": " + std::string(image) + " is " + std::to_string(width_px) +
              "x" + std::to_string(height_px) + " but the camera is " +
              std::to_string(camera_width_px) + "x" + std::to_string(camera_height_px) +
              std::string(fix));
}

}  // namespace pensight
