#include "sim/truth_depth.h"

#include "sim/render_cpu.h"

namespace pensight::sim {

ImageF32 truth_depth(const Scenario& s, const NetGeometry& net, const PinholeCamera& cam,
                     const Eigen::Isometry3d& T_pen_camera, int stride) {
  ImageF32 depth(cam.width_px, cam.height_px, 0.0f);
  const double range = net_visible_range_m(s.water);
  const Eigen::Vector3d o = T_pen_camera.translation();
  for (int y = 0; y < cam.height_px; y += stride) {
    for (int x = 0; x < cam.width_px; x += stride) {
      const Eigen::Vector3d ray_C = cam.ray(Eigen::Vector2d(x, y));
      const Eigen::Vector3d d = (T_pen_camera.linear() * ray_C).normalized();
      const auto hit = net.intersect(o, d);
      if (!hit || hit->t > range) continue;
      if (d.z() < 0 && -o.z() / d.z() <= hit->t) continue;  // the surface comes first
      depth.at(x, y) = static_cast<float>(hit->t / ray_C.norm());
    }
  }
  return depth;
}

}  // namespace pensight::sim
