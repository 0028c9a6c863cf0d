#pragma once
// Min/max pyramid of a depth image, for the projective integrator's footprint tests: per block of
// 2^k x 2^k pixels the nearest depth (0 where any pixel has no valid depth, so a footprint with a
// hole is never cleared) and the farthest (what lies beyond it is hidden). Building it reads each
// pixel once and writes 4/3 of the image per channel; a query reads at most 3x3 blocks.
#include <vector>

#include "core/image.h"

namespace pensight::mapping {

class DepthPyramid {
 public:
  // Bounds over a footprint; near = 0 when any pixel in it has no valid depth.
  struct Bounds {
    float near_m = 0;
    float far_m = 0;
  };

  // depth_m: z-depth per pixel. Pixels with depth 0, NaN, negative or below min_range_m are
  // unknown (near and far 0); beyond max_range_m they clear the space up to it (near +inf, far
  // max_range_m). Reuses its buffers when the size is unchanged.
  void build(const ImageF32& depth_m, float min_range_m, float max_range_m);

  int width() const { return width_; }
  int height() const { return height_; }

  // Bounds over the integer pixel rectangle [x0, x1] x [y0, y1] (clamped to the image), taken
  // from the level whose blocks of 2^k pixels are at least half the rectangle's larger extent e:
  // the blocks it touches, a superset reaching less than one block (2^k < e) beyond each side,
  // so at most 3e - 2 pixels per axis (e = 10 from x = 7 reads pixels 0-23). near is a lower and
  // far an upper bound.
  Bounds query(int x0, int y0, int x1, int y1) const;

 private:
  struct Level {
    int width = 0, height = 0;
    std::vector<float> near_m, far_m;
  };
  int width_ = 0, height_ = 0;
  std::vector<Level> levels_;
};

}  // namespace pensight::mapping
