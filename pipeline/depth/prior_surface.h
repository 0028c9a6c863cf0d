#pragma once
// The prior surface: the smooth surface through a frame's sparse depths that the depth network
// corrects (its third prior channel, Q). A quadric in inverse depth,
//   t(u, v) = m_ref / z = c0 + c1 u + c2 v + c3 u^2 + c4 u v + c5 v^2,
// over u = (x - (W-1)/2) / (W/2), v = (y - (H-1)/2) / (W/2) (pixel centres at integers), fitted
// by least squares weighted by the points' quality (all 1 when none is positive), where m_ref is
// the weighted mean depth. A plane in the camera frame is linear in inverse depth over the image
// (1/z = (n . ray) / d), so t is exact for a flat net and its quadratic terms take a cylinder's
// curvature and the slow bends of a deformed net.
//
// Ridge (relative to the sum of the weights): 0 on c0; 1e-6 on the slopes, so that a row of
// points leaves the slope across it at 0 instead of undetermined; 1e-3 on the curvatures, so
// that points from one ROI (spread over a tenth of the image, u^4 ~ 1e-4) give a plane while
// points over the frame (u^4 ~ 0.1) move them by about 1 %. scripts/train_depth.py repeats this
// fit in numpy for the training data; the two must stay equal.
//
// The net's own curvature: a camera inside a pen sees the wall curve towards it beyond the
// priors (at 1 m from a 12 m pen, 2.5 % nearer at the image's edge), so with a NetWallShape the
// curvatures are pulled towards that cylinder's instead of towards 0. A vertical cylinder of
// curvature k seen along the normal n (camera frame, from the first fit's plane part) with its
// horizontal tangent h has 1/z = (n . r) / d + k (h . r)^2 / (2 n . r) to second order in the
// ray r = (s u, s v, 1), s = (W/2) / f. For a camera without roll (the vertical lies in its y-z
// plane) the quadratic part of m_ref / z is m_ref k s^2 u^2 / (2 n_z (n_y^2 + n_z^2)): u^2 only.
// A plane steeper than 45 deg from the vertical (the pen's bottom) keeps the pull towards 0.
//
// Cost: O(points) for the fit (one or two 6x6 solves), O(W H) to render. Method: weighted ridge
// least squares (Hoerl and Kennard 1970) on the normal equations, solved by Eigen's LDLT.
#include <array>
#include <span>
#include <vector>

#include "pipeline/fft/net_geometry.h"

namespace pensight {

struct PriorSurface {
  std::array<double, 6> c{};    // c0 .. c5 above
  double m_ref_m = 0;           // weighted mean depth of the points
  double t_min = 0, t_max = 0;  // m_ref / z over the points
  int width = 0, height = 0;    // the pixel grid u, v refer to
};

// The net wall's shape as the fit knows it: a vertical cylinder of this curvature (1 / the pen's
// radius; 0 for a flat panel: net_curvature_per_m(SceneConfig)) seen through a focal length of
// focal_px in the fit's pixels. The default (0) fits without it.
struct NetWallShape {
  double curvature_per_m = 0;
  double focal_px = 0;
};

// depths: in the width x height image's pixels (e.g. network_depths()). Throws pensight::Error
// when there is no point or a depth is not positive and finite.
PriorSurface fit_prior_surface(std::span<const SparseDepth> depths, int width, int height,
                               const NetWallShape& wall = {});

// Q = m_ref / clamp(t(u, v), t_min / 2, 2 t_max) at every pixel centre (depth in metres, between
// half the nearest and twice the farthest point's depth), row-major into out[0, W*H).
void render_prior_surface(const PriorSurface& surface, std::span<float> out);

// A depth grid (width x height, row-major, metres; e.g. a network's output) multiplied by the
// prior surface fitted through the ratios prior / grid at the priors' pixels (snapped to the
// grid; pixels without a positive finite value are skipped; none left: unchanged). The priors,
// accurate to a few per mille on a frontal net, fix the metric scale and the slow shape; the grid
// keeps its detail between and beyond them. Cost: O(points + W H).
void align_to_priors(std::vector<float>& depth_m, int width, int height,
                     std::span<const SparseDepth> depths);

}  // namespace pensight
