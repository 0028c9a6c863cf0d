#include "sim/optics.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <cstring>
#include <numbers>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <thread>
#include <vector>

#include "core/error.h"
#include "core/threads.h"
#include "sim/sim_hash.h"

namespace pensight::sim {
namespace {

// Rows split over the cores, as the CPU renderer does.
template <class F>
void for_rows(int height, F&& row) {
  const int threads = worker_threads(0);
  std::vector<std::jthread> pool;
  for (int t = 0; t < threads; ++t) {
    pool.emplace_back([&, t] {
      for (int y = t; y < height; y += threads) row(y);
    });
  }
}

double gaussian(uint32_t h1, uint32_t h2) {
  const double u1 = (static_cast<double>(h1 >> 8) + 0.5) * (1.0 / 16777216.0);
  return std::sqrt(-2 * std::log(u1)) * std::cos(2 * std::numbers::pi * unit_float(h2));
}

// Bilinear, clamped to the image (the motion segment may leave the frame); frames are at least
// 8 x 8 pixels (scenario.cpp).
double sample(const ImageF32& img, double x, double y) {
  x = std::clamp(x, 0.0, img.width - 1.0);
  y = std::clamp(y, 0.0, img.height - 1.0);
  const int x0 = std::min(static_cast<int>(x), img.width - 2);
  const int y0 = std::min(static_cast<int>(y), img.height - 2);
  const int x1 = x0 + 1, y1 = y0 + 1;
  const double fx = x - x0, fy = y - y0;
  const double top = img.at(x0, y0) + fx * (img.at(x1, y0) - img.at(x0, y0));
  const double bottom = img.at(x0, y1) + fx * (img.at(x1, y1) - img.at(x0, y1));
  return top + fy * (bottom - top);
}

cv::Mat jpeg(const cv::Mat& m, int quality, int read_flag) {
  if (quality < 1 || quality > 100) throw Error("jpeg_quality must be 1 to 100");
  std::vector<uchar> bytes;
  if (!cv::imencode(".jpg", m, bytes, {cv::IMWRITE_JPEG_QUALITY, quality})) {
    throw Error("cannot encode a frame as JPEG");
  }
  cv::Mat out = cv::imdecode(bytes, read_flag);
  if (out.empty() || out.size() != m.size()) throw Error("cannot decode a JPEG frame");
  return out;
}

}  // namespace

bool optics_enabled(const CameraConfig& c) {
  return c.focus_distance_m > 0 || c.exposure_time_s > 0 || c.colour || c.jpeg_quality > 0;
}

double blur_circle_px(const CameraConfig& c, double depth_m) {
  if (!(c.focus_distance_m > 0)) return 0;
  // Thin lens, focal length f = fx * pitch, aperture A = f / N, focused at d_f: a point at d
  // images to a disc of diameter A f |1/d_f - 1/d| / (1 - f/d_f) on the sensor; in pixels
  // (divided by the pitch) that is fx A |1/d_f - 1/d| / (1 - f/d_f).
  const double fx = c.calibration.camera.fx_px;
  const double f = fx * c.pixel_pitch_m, aperture = f / c.f_number;
  const double inv_d = depth_m > 0 ? 1 / depth_m : 0;
  return fx * aperture * std::abs(1 / c.focus_distance_m - inv_d) / (1 - f / c.focus_distance_m);
}

ImageF32 defocus(const ImageF32& grey, const ImageF32& depth_m, const CameraConfig& c) {
  if (!(c.focus_distance_m > 0)) return grey;
  ImageF32 out(grey.width, grey.height);
  for_rows(grey.height, [&](int y) {
    for (int x = 0; x < grey.width; ++x) {
      const double radius = std::min(blur_circle_px(c, depth_m.at(x, y)), kMaxBlurCircle_px) / 2;
      // Anti-aliased disc: weight 1 inside, falling linearly to 0 across the pixel at its rim;
      // below half a pixel only the centre counts.
      const int reach = static_cast<int>(std::floor(radius + 0.5));
      if (reach < 1) {
        out.at(x, y) = grey.at(x, y);
        continue;
      }
      double sum = 0, weight = 0;
      for (int dy = -reach; dy <= reach; ++dy) {
        const int yy = y + dy;
        if (yy < 0 || yy >= grey.height) continue;
        for (int dx = -reach; dx <= reach; ++dx) {
          const int xx = x + dx;
          if (xx < 0 || xx >= grey.width) continue;
          const double w = std::clamp(radius + 0.5 - std::hypot(dx, dy), 0.0, 1.0);
          sum += w * grey.at(xx, yy);
          weight += w;
        }
      }
      out.at(x, y) = static_cast<float>(sum / weight);
    }
  });
  return out;
}

CameraMotion camera_motion(const Scenario& s, const FrameState& f) {
  const Eigen::Matrix3d R_pb = f.body.T_pen_body.linear();
  const Eigen::Matrix3d R_bc = s.camera.calibration.T_body_camera.linear();
  const Eigen::Vector3d p_bc = s.camera.calibration.T_body_camera.translation();
  const Eigen::Vector3d w_b = f.body.angular_velocity_body_radps;
  // The camera sits off the body origin, so the turn adds w x p to its velocity.
  const Eigen::Vector3d v_pen = f.body.velocity_pen_mps + R_pb * w_b.cross(p_bc);
  CameraMotion m;
  m.velocity_c_mps = (R_pb * R_bc).transpose() * v_pen;
  m.angular_velocity_c_radps = R_bc.transpose() * w_b;
  return m;
}

Eigen::Vector2d image_velocity_pxps(const PinholeCamera& cam, const CameraMotion& m, double x_px,
                                    double y_px, double depth_m) {
  // A still point P = Z q (q = (x, y, 1)) moves in C as dP/dt = -v - w x P; divided by Z, the
  // normalised image point moves by (dP/Z)_xy - q_xy (dP/Z)_z.
  const Eigen::Vector3d q((x_px - cam.cx_px) / cam.fx_px, (y_px - cam.cy_px) / cam.fy_px, 1);
  const double inv_z = depth_m > 0 ? 1 / depth_m : 0;
  const Eigen::Vector3d dp = -m.velocity_c_mps * inv_z - m.angular_velocity_c_radps.cross(q);
  return {cam.fx_px * (dp.x() - q.x() * dp.z()), cam.fy_px * (dp.y() - q.y() * dp.z())};
}

ImageF32 motion_blur(const ImageF32& grey, const ImageF32& depth_m, const PinholeCamera& cam,
                     const CameraMotion& m, double exposure_time_s) {
  if (!(exposure_time_s > 0)) return grey;
  ImageF32 out(grey.width, grey.height);
  for_rows(grey.height, [&](int y) {
    for (int x = 0; x < grey.width; ++x) {
      const Eigen::Vector2d step =
          exposure_time_s * image_velocity_pxps(cam, m, x, y, depth_m.at(x, y));
      // About one sample per pixel of the segment, at the midpoints of equal parts.
      const int n = static_cast<int>(std::ceil(step.norm())) + 1;
      double sum = 0;
      for (int i = 0; i < n; ++i) {
        const double s = (i + 0.5) / n - 0.5;
        sum += sample(grey, x + s * step.x(), y + s * step.y());
      }
      out.at(x, y) = static_cast<float>(sum / n);
    }
  });
  return out;
}

std::array<double, 3> veil_colour() {
  // Blue-green water light, scaled to luma 1 (ITU-R BT.601 weights, as the dataset reader's
  // grey conversion) so that the grey model's veil keeps its brightness.
  const std::array<double, 3> v = {0.3, 1.0, 0.8};
  const double luma = 0.299 * v[0] + 0.587 * v[1] + 0.114 * v[2];
  return {v[0] / luma, v[1] / luma, v[2] / luma};
}

std::array<ImageF32, 3> water_colour(const ImageF32& grey, const ImageF32& depth_m,
                                     const Scenario& s, const FrameState& f) {
  const PinholeCamera& cam = s.camera.calibration.camera;
  const double c = s.water.attenuation_per_m;
  const double z = std::max(f.T_pen_camera.translation().z(), 0.0);
  // The grey veil at the camera (the renderers' background), in grey levels before vignetting.
  const double veil = 255.0 * s.camera.exposure * s.water.backscatter * s.light.ambient *
                      std::exp(-s.water.diffuse_attenuation_per_m * z);
  const std::array<double, 3> tint = veil_colour();
  std::array<ImageF32, 3> out;
  for (ImageF32& channel : out) channel = ImageF32(grey.width, grey.height);
  for_rows(grey.height, [&](int y) {
    for (int x = 0; x < grey.width; ++x) {
      const double L = grey.at(x, y), depth = depth_m.at(x, y);
      const Eigen::Vector3d ray = cam.ray({static_cast<double>(x), static_cast<double>(y)});
      for (int k = 0; k < 3; ++k) {
        double value = L * tint[k];
        if (depth > 0) {
          // L = J T + B (1 - T) in grey: the object's share J T is re-attenuated over the path
          // length t with the channel's c_k, the veil takes the channel's colour.
          const double t = depth * ray.norm(), T = std::exp(-c * t);
          const double B = veil * std::pow(1 / ray.norm(), 4 * s.camera.vignetting);
          const double object = std::max(L - B * (1 - T), 0.0);
          const double Tk = std::exp(-c * kChannelAttenuation[k] * t);
          value = object * Tk / T + B * tint[k] * (1 - Tk);
        }
        out[k].at(x, y) = static_cast<float>(value);
      }
    }
  });
  return out;
}

uint32_t noise_frame_key(const Scenario& s, int frame) {
  return hash3(static_cast<uint32_t>(frame), fold_seed(s.seed), kStreamNoise);
}

uint8_t sensor_value(double grey, uint32_t pixel, uint32_t frame_key, uint32_t channel,
                     const CameraConfig& c, bool noise) {
  if (noise) {
    const double sigma =
        std::sqrt(c.read_noise * c.read_noise + c.shot_noise * c.shot_noise * std::max(grey, 0.0));
    const uint32_t h = hash2(pixel, frame_key, channel);
    grey += sigma * gaussian(h, hash32(h));
  }
  return static_cast<uint8_t>(std::clamp(std::floor(grey + 0.5), 0.0, 255.0));
}

ImageU8 jpeg_round_trip(const ImageU8& image, int quality) {
  const cv::Mat in(image.height, image.width, CV_8UC1, const_cast<uint8_t*>(image.pixels.data()));
  const cv::Mat out = jpeg(in, quality, cv::IMREAD_GRAYSCALE);
  ImageU8 r(image.width, image.height);
  std::copy(out.datastart, out.dataend, r.pixels.begin());
  return r;
}

ImageRgb8 jpeg_round_trip(const ImageRgb8& image, int quality) {
  static_assert(sizeof(ImageRgb8::pixels[0]) == 3);
  const cv::Mat rgb(image.height, image.width, CV_8UC3,
                    const_cast<std::array<uint8_t, 3>*>(image.pixels.data()));
  cv::Mat bgr;
  cv::cvtColor(rgb, bgr, cv::COLOR_RGB2BGR);  // OpenCV's channel order
  cv::Mat out = jpeg(bgr, quality, cv::IMREAD_COLOR);
  cv::cvtColor(out, out, cv::COLOR_BGR2RGB);
  ImageRgb8 r(image.width, image.height);
  std::memcpy(r.pixels.data(), out.data, r.pixels.size() * 3);
  return r;
}

void apply_optics(const Scenario& s, const FrameState& f, const RenderOptions& o,
                  RenderedFrame& r) {
  const CameraConfig& c = s.camera;
  const PinholeCamera& cam = c.calibration.camera;
  std::vector<ImageF32> channels;
  if (c.colour) {
    for (ImageF32& channel : water_colour(r.radiance, r.depth_m, s, f)) {
      channels.push_back(std::move(channel));
    }
  } else {
    channels.push_back(r.radiance);
  }
  const CameraMotion motion = camera_motion(s, f);
  const uint32_t key = noise_frame_key(s, f.frame);
  std::vector<ImageU8> quantised;
  for (size_t k = 0; k < channels.size(); ++k) {
    const ImageF32 blurred =
        motion_blur(defocus(channels[k], r.depth_m, c), r.depth_m, cam, motion, c.exposure_time_s);
    ImageU8 q(blurred.width, blurred.height);
    for (size_t i = 0; i < q.pixels.size(); ++i) {
      q.pixels[i] = sensor_value(blurred.pixels[i], static_cast<uint32_t>(i), key,
                                 static_cast<uint32_t>(k), c, o.noise);
    }
    quantised.push_back(std::move(q));
  }
  if (c.colour) {
    r.image_rgb = ImageRgb8(cam.width_px, cam.height_px);
    for (size_t i = 0; i < r.image_rgb.pixels.size(); ++i) {
      r.image_rgb.pixels[i] = {quantised[0].pixels[i], quantised[1].pixels[i],
                               quantised[2].pixels[i]};
    }
    if (c.jpeg_quality > 0) r.image_rgb = jpeg_round_trip(r.image_rgb, c.jpeg_quality);
  } else {
    r.image = std::move(quantised[0]);
    if (c.jpeg_quality > 0) r.image = jpeg_round_trip(r.image, c.jpeg_quality);
  }
}

}  // namespace pensight::sim
