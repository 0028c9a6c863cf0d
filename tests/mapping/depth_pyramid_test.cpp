// DepthPyramid::query against brute-force scans of the same pixels, on random depth images with
// holes (0, NaN, negative, below min range) and depths beyond max range.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>

#include "mapping/depth_pyramid.h"

namespace pensight::mapping {
namespace {

constexpr float kMinRange = 0.1f, kMaxRange = 5.0f;
constexpr float kInf = std::numeric_limits<float>::infinity();

// The documented per-pixel rule: unknown pixels count as near = far = 0, pixels beyond max range
// as near = +inf, far = max range.
bool valid(float d) {
  return std::isfinite(d) && d >= kMinRange && d > 0;
}
float pixel_near(float d) {
  return !valid(d) ? 0.0f : (d > kMaxRange ? kInf : d);
}
float pixel_far(float d) {
  return !valid(d) ? 0.0f : std::min(d, kMaxRange);
}

struct Rect {
  int x0, y0, x1, y1;
};

DepthPyramid::Bounds brute_force(const ImageF32& depth, Rect r) {
  DepthPyramid::Bounds b{kInf, 0.0f};
  for (int y = r.y0; y <= r.y1; ++y) {
    for (int x = r.x0; x <= r.x1; ++x) {
      b.near_m = std::min(b.near_m, pixel_near(depth.at(x, y)));
      b.far_m = std::max(b.far_m, pixel_far(depth.at(x, y)));
    }
  }
  return b;
}

bool holds_hole(const ImageF32& depth, Rect r) {
  for (int y = r.y0; y <= r.y1; ++y) {
    for (int x = r.x0; x <= r.x1; ++x) {
      if (!valid(depth.at(x, y))) return true;
    }
  }
  return false;
}

// The pixels the query reads (depth_pyramid.h): the rectangle clamped to the image, widened to
// the blocks of 2^k pixels of the level whose blocks are at least half its larger extent.
Rect documented_superset(Rect r, int width, int height) {
  const int extent = std::max(r.x1 - r.x0, r.y1 - r.y0) + 1;
  int k = 0;
  while ((2 << k) < extent) ++k;
  const int block = 1 << k;
  return {(r.x0 >> k) * block, (r.y0 >> k) * block,
          std::min(((r.x1 >> k) + 1) * block - 1, width - 1),
          std::min(((r.y1 >> k) + 1) * block - 1, height - 1)};
}

ImageF32 random_depth(std::mt19937& rng, int width, int height, double hole_share) {
  ImageF32 depth(width, height);
  std::uniform_real_distribution<float> depth_m(0.02f, 7.0f);  // below min and beyond max range
  std::uniform_real_distribution<double> u(0, 1);
  for (float& d : depth.pixels) {
    const double h = u(rng);
    if (h < hole_share / 3) {
      d = 0.0f;
    } else if (h < 2 * hole_share / 3) {
      d = std::numeric_limits<float>::quiet_NaN();
    } else if (h < hole_share) {
      d = -depth_m(rng);
    } else {
      d = depth_m(rng);
    }
  }
  return depth;
}

// A side of 1 to n pixels, log-uniform so small and large rectangles both occur.
int random_side(std::mt19937& rng, int n) {
  std::uniform_real_distribution<double> log_side(0.0, std::log(static_cast<double>(n) + 1));
  return std::max(1, static_cast<int>(std::exp(log_side(rng))));
}

TEST(DepthPyramidTest, PixelRule) {
  ImageF32 depth(6, 1);
  depth.pixels = {0.0f, std::numeric_limits<float>::quiet_NaN(), -1.0f, 0.05f, 2.0f, 9.0f};
  DepthPyramid p;
  p.build(depth, kMinRange, kMaxRange);
  const float near[] = {0, 0, 0, 0, 2.0f, kInf}, far[] = {0, 0, 0, 0, 2.0f, kMaxRange};
  for (int x = 0; x < 6; ++x) {
    const DepthPyramid::Bounds b = p.query(x, 0, x, 0);
    EXPECT_EQ(b.near_m, near[x]) << "pixel " << x;
    EXPECT_EQ(b.far_m, far[x]) << "pixel " << x;
  }
  const DepthPyramid::Bounds both = p.query(4, 0, 5, 0);
  EXPECT_EQ(both.near_m, 2.0f);
  EXPECT_EQ(both.far_m, kMaxRange);
  // Entirely outside the image: nothing known.
  const DepthPyramid::Bounds outside = p.query(7, 0, 9, 0);
  EXPECT_EQ(outside.near_m, 0.0f);
  EXPECT_EQ(outside.far_m, 0.0f);
}

TEST(DepthPyramidTest, QueryBoundsTheRectangleFromItsDocumentedSuperset) {
  std::mt19937 rng(20240613);
  struct Size {
    int w, h;
  };
  std::vector<Size> sizes = {{721, 539}, {720, 540}, {1, 1}, {1, 9}, {13, 1}, {160, 120}, {3, 2}};
  std::uniform_int_distribution<int> side(1, 400);
  for (int i = 0; i < 12; ++i) sizes.push_back({side(rng), side(rng)});
  const double hole_shares[] = {0.0, 0.001, 0.03, 0.5};
  DepthPyramid pyramid;  // one pyramid for every image: rebuilding at a new size must not matter
  int with_hole = 0, without_hole = 0, widened = 0;
  for (size_t s = 0; s < sizes.size(); ++s) {
    const auto [w, h] = sizes[s];
    const ImageF32 depth = random_depth(rng, w, h, hole_shares[s % 4]);
    pyramid.build(depth, kMinRange, kMaxRange);
    ASSERT_EQ(pyramid.width(), w);
    ASSERT_EQ(pyramid.height(), h);
    for (int q = 0; q < 300; ++q) {
      // Rectangles that may reach past the image's edges (the query clamps them).
      const int rw = random_side(rng, w + 3), rh = random_side(rng, h + 3);
      const int x0 = std::uniform_int_distribution<int>(-2, w + 1 - rw)(rng);
      const int y0 = std::uniform_int_distribution<int>(-2, h + 1 - rh)(rng);
      const Rect asked{x0, y0, x0 + rw - 1, y0 + rh - 1};
      const Rect r{std::max(asked.x0, 0), std::max(asked.y0, 0), std::min(asked.x1, w - 1),
                   std::min(asked.y1, h - 1)};
      const DepthPyramid::Bounds b = pyramid.query(asked.x0, asked.y0, asked.x1, asked.y1);
      SCOPED_TRACE(::testing::Message() << w << "x" << h << " rect [" << r.x0 << ", " << r.x1
                                        << "] x [" << r.y0 << ", " << r.y1 << "]");
      if (r.x1 < r.x0 || r.y1 < r.y0) {  // wholly outside the image: nothing known
        EXPECT_EQ(b.near_m, 0.0f);
        EXPECT_EQ(b.far_m, 0.0f);
        continue;
      }
      const DepthPyramid::Bounds exact = brute_force(depth, r);
      EXPECT_LE(b.near_m, exact.near_m);
      EXPECT_GE(b.far_m, exact.far_m);
      if (holds_hole(depth, r)) {
        EXPECT_EQ(b.near_m, 0.0f);
        ++with_hole;
      } else {
        ++without_hole;
      }
      // The bounds are exactly those of the documented superset, which reaches less than one
      // block beyond the rectangle on each side: at most 3x the rectangle's larger extent.
      const Rect sup = documented_superset(r, w, h);
      const DepthPyramid::Bounds from_sup = brute_force(depth, sup);
      EXPECT_EQ(b.near_m, from_sup.near_m);
      EXPECT_EQ(b.far_m, from_sup.far_m);
      const int extent = std::max(r.x1 - r.x0, r.y1 - r.y0) + 1;
      EXPECT_LE(sup.x1 - sup.x0 + 1, extent <= 2 ? r.x1 - r.x0 + 1 : 3 * extent - 2);
      EXPECT_LE(sup.y1 - sup.y0 + 1, extent <= 2 ? r.y1 - r.y0 + 1 : 3 * extent - 2);
      widened += (sup.x1 - sup.x0 > r.x1 - r.x0) || (sup.y1 - sup.y0 > r.y1 - r.y0);
    }
  }
  // Both kinds of rectangle and widened supersets occur, else the checks above test little
  // (measured with this seed: 3472 with a hole, 1505 without, 4290 widened; bounds 1/3 of the
  // smallest).
  EXPECT_GT(with_hole, 500);
  EXPECT_GT(without_hole, 500);
  EXPECT_GT(widened, 500);
}

}  // namespace
}  // namespace pensight::mapping
