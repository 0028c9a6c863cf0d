#pragma once
// Pinhole camera with radial-tangential (Brown-Conrady k1, k2, p1, p2) distortion, as in the
// EuRoC/Kalibr cam0/sensor.yaml of ../shared/dataset-format.md. Camera frame C: OpenCV, x right,
// y down, z along the optical axis. Pixel centres are at integer coordinates.
#include <Eigen/Core>
#include <cstdint>
#include <optional>
#include <string_view>

#include "core/default_camera.h"

namespace pensight {

struct PinholeCamera {
  int width_px = kDefaultImageWidth_px;
  int height_px = kDefaultImageHeight_px;
  double fx_px = kDefaultFocalLength_px;
  double fy_px = kDefaultFocalLength_px;
  double cx_px = (kDefaultImageWidth_px - 1) / 2.0;
  double cy_px = (kDefaultImageHeight_px - 1) / 2.0;
  double k1 = 0, k2 = 0, p1 = 0, p2 = 0;

  bool has_distortion() const { return k1 != 0 || k2 != 0 || p1 != 0 || p2 != 0; }

  // Normalised image coordinates (x/z, y/z) -> distorted normalised coordinates.
  Eigen::Vector2d distort(const Eigen::Vector2d& xn) const;
  // Inverse of distort (fixed-point iteration; exact to ~1e-12 for realistic lenses).
  Eigen::Vector2d undistort(const Eigen::Vector2d& xd) const;

  // Point in C -> pixel; nullopt when the point is not in front of the camera (z <= 0).
  std::optional<Eigen::Vector2d> project(const Eigen::Vector3d& p_C) const;
  // Pixel -> ray direction in C with z = 1 (not unit length).
  Eigen::Vector3d ray(const Eigen::Vector2d& px) const;

  bool in_image(const Eigen::Vector2d& px) const {
    return px.x() >= -0.5 && px.y() >= -0.5 && px.x() < width_px - 0.5 && px.y() < height_px - 0.5;
  }
  // Same camera for an image resized by `scale` (e.g. 320/720 for the depth network input).
  PinholeCamera scaled(double scale) const;
};

// The default camera's field of view (kDefaultFocalLength_px at kDefaultImageWidth_px wide) on a
// frame of another size: fx = fy scaled with the width, principal point at the centre, no
// distortion. The same scene seen by a camera with more or fewer pixels.
PinholeCamera default_field_of_view(int width_px, int height_px);

// Throws pensight::Error "<what>: <image> is WxH but the camera is WxH<fix>" where an image's size
// (as read, 64-bit: a damaged header can claim any) is not the camera's; `image` names it
// ("image", "depth image"), `fix` says what to give instead.
void check_image_size(int64_t width_px, int64_t height_px, int camera_width_px,
                      int camera_height_px, std::string_view what, std::string_view image = "image",
                      std::string_view fix = "");
inline void check_image_size(int64_t width_px, int64_t height_px, const PinholeCamera& camera,
                             std::string_view what, std::string_view image = "image",
                             std::string_view fix = "") {
  check_image_size(width_px, height_px, camera.width_px, camera.height_px, what, image, fix);
}

}  // namespace pensight
