#pragma once
// Fit of a circle of KNOWN radius to 2D points: the horizontal trace of a vertical cylindrical net
// seen from inside. Geometric (orthogonal-distance) least squares by Gauss-Newton with Huber
// weights, started from the best of an algebraic line-fit hypothesis and 2-point minimal
// hypotheses scored by MSAC, so gross outliers (bad ROIs) do not pull the fit.
//
// The circle is parametrised by the direction theta of the outward normal at the points' centroid
// m and the signed offset d of the circle from m along it: centre = m - (R + d) n(theta). Both
// parameters are well determined whatever R, so a flat net (R = 100 m and more) is as well
// conditioned as a 12 m pen; the centre's own coordinates are not when R >> the point spread.
//
// Precondition: the observer (origin of the points' frame) is inside the circle; of the two
// circles through a pair of points the one whose centre is nearer the origin is taken.
#include <Eigen/Core>
#include <span>

#include "pipeline/global_pose/pen_geometry.h"

namespace pensight::global_pose {

struct CircleFitOptions {
  double radius_m = kDefaultPenRadius_m;
  // Residuals beyond this are down-weighted (Huber); about 2-3x the point noise.
  double huber_delta_m = 0.03;
  // Points farther than this from the circle are outliers: excluded from the final fit.
  double outlier_threshold_m = 0.15;
  int max_iterations = 15;
  int max_hypotheses = 64;  // most 2-point MSAC hypotheses (deterministic, adaptive count)
  int min_inliers = 3;
};

struct CircleFit {
  bool ok = false;
  Eigen::Vector2d centre = {kNaN, kNaN};
  Eigen::Matrix2d centre_covariance = Eigen::Matrix2d::Constant(kNaN);
  double residual_rms_m = kNaN;  // over inliers
  int inliers = 0;
  // Spread of the inliers' bearings seen from the origin (the observer): a fit over a narrow
  // wedge (a few ROIs at the image edge) pins the centre poorly whatever its residuals say.
  double inlier_bearing_spread_rad = 0;
  int iterations = 0;
};

// Points with a non-finite coordinate or a weight <= 0 are ignored. `weights` (optional, one per
// point, else pensight::Error) scale each point's influence, e.g. the FFT quality of its ROI.
// Fewer than 3 usable points or a degenerate set give ok = false and NaN, not an error.
CircleFit fit_circle_known_radius(std::span<const Eigen::Vector2d> points,
                                  const CircleFitOptions& options,
                                  std::span<const double> weights = {});

}  // namespace pensight::global_pose
