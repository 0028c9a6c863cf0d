#pragma once
// The lamps' veil (lamp_veil.h) tabulated over a camera's image for the Vulkan renderer. The
// lamps ride with the camera, so for each pixel the veil depends only on where the ray ends;
// the table holds it on a grid of pixels every kStep_px and kNodes ray ends, evenly spaced in
// ln(1 + t / kLampVeilScale_m) up to the visible range, and the shader interpolates it
// (bilinear over the pixel, linear along the ray) instead of running the quadrature per pixel.
//
// Cost: building it runs lamp_veil at (width / kStep_px + 1) x (height / kStep_px + 1) x kNodes
// points (0.1 M for 720x540, about 30 ms, once per scenario); a lookup reads two vec4.
// Accuracy: tests/sim/lamp_veil bounds the interpolation against lamp_veil itself.
#include <array>
#include <vector>

#include "core/camera.h"
#include "sim/frame_state.h"

namespace pensight::sim {

class LampVeilTable {
 public:
  static constexpr int kStep_px = 16;  // render.comp VEIL_STEP_PX
  static constexpr int kNodes = 64;    // render.comp VEIL_NODES

  // lamps_camera: the lamps in the camera frame C; range_m: where rays are cut (the visible
  // range, net_visible_range_m); strength: water.lamp_backscatter, folded into the values.
  LampVeilTable(const PinholeCamera& camera, const std::vector<LampPose>& lamps_camera,
                double attenuation_per_m, double strength, double range_m);

  // The veil for pixel (x_px, y_px) (pixel centres at integers; -0.5..width-0.5) and a ray cut
  // at t_m (> range_m is the range), exactly as the shader interpolates it.
  double at(double x_px, double y_px, double t_m) const;

  // Per cell (row-major, cells_x() x cells_y()) and node: the values at the cell's corners
  // (x0 y0, x1 y0, x0 y1, x1 y1), the layout of the shader's VeilBuf.
  const std::vector<std::array<float, 4>>& cells() const { return cells_; }
  int cells_x() const { return cells_x_; }
  int cells_y() const { return cells_y_; }

 private:
  int cells_x_, cells_y_;
  double w_max_;
  std::vector<std::array<float, 4>> cells_;
};

}  // namespace pensight::sim
