#include "pipeline/depth/depth_plane.h"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

#include "core/error.h"
#include "core/median.h"
#include "core/net_angles.h"

namespace pensight {
namespace {

struct Sample {
  double x, y, z;  // back-projected point in C
  bool central;    // in the d_net window
};

}  // namespace

PixelRays::PixelRays(const PinholeCamera& camera)
    : width(camera.width_px), height(camera.height_px), centre_px(camera.cx_px, camera.cy_px) {
  xy.reserve(static_cast<size_t>(width) * height);
  for (int v = 0; v < height; ++v) {
    for (int u = 0; u < width; ++u) xy.push_back(camera.ray({u, v}).head<2>().cast<float>());
  }
}

DepthPlanePose depth_plane_pose(const ImageF32& depth_m, const PixelRays& rays,
                                const DepthPlaneParams& params) {
  if (depth_m.width != rays.width || depth_m.height != rays.height) {
    throw Error("depth plane: the depth image is " + std::to_string(depth_m.width) + "x" +
                std::to_string(depth_m.height) + " but the camera " + std::to_string(rays.width) +
                "x" + std::to_string(rays.height));
  }
  DepthPlanePose out;
  std::vector<Sample> samples;
  samples.reserve(depth_m.pixels.size());
  const double hw = 0.5 * params.central_share * depth_m.width;
  const double hh = 0.5 * params.central_share * depth_m.height;
  for (int v = 0; v < depth_m.height; ++v) {
    for (int u = 0; u < depth_m.width; ++u) {
      const float d = depth_m.at(u, v);
      if (!(d > 0) || !std::isfinite(d)) continue;
      const Eigen::Vector2f& r = rays.xy[static_cast<size_t>(v) * rays.width + u];
      samples.push_back(
          {r.x() * static_cast<double>(d), r.y() * static_cast<double>(d), d,
           std::abs(u - rays.centre_px.x()) <= hw && std::abs(v - rays.centre_px.y()) <= hh});
    }
  }
  if (static_cast<double>(samples.size()) <
      params.min_valid_share * static_cast<double>(depth_m.pixels.size())) {
    out.reason = "only " + std::to_string(samples.size()) + " pixels with depth";
    return out;
  }
  auto residual = [&](const Eigen::Vector3d& abc, const Sample& p) {
    return std::abs(p.z - abc.x() * p.x - abc.y() * p.y - abc.z());
  };
  // Start: the three-pixel plane that most pixels of a strided subset agree with, so a fish
  // covering a quarter of the view cannot pull the least-squares start off the net.
  Eigen::Vector3d abc = Eigen::Vector3d::Zero();
  {
    std::mt19937 rng(1);  // fixed: the same frame always gives the same pose
    std::uniform_int_distribution<size_t> pick(0, samples.size() - 1);
    const size_t stride = std::max<size_t>(1, samples.size() / 2000);
    size_t best = 0;
    for (int h = 0; h < params.hypotheses; ++h) {
      Eigen::Matrix3d A;
      Eigen::Vector3d b;
      for (int k = 0; k < 3; ++k) {
        const Sample& p = samples[pick(rng)];
        A.row(k) << p.x, p.y, 1;
        b(k) = p.z;
      }
      const Eigen::FullPivLU<Eigen::Matrix3d> lu(A);
      if (!lu.isInvertible()) continue;
      const Eigen::Vector3d cand = lu.solve(b);
      size_t agree = 0;
      for (size_t i = 0; i < samples.size(); i += stride) {
        agree += residual(cand, samples[i]) < params.inlier_rel * samples[i].z;
      }
      if (agree > best) {
        best = agree;
        abc = cand;
      }
    }
    if (best == 0) {
      out.reason = "the depth image spans no plane";
      return out;
    }
  }
  // Refinement over every pixel: iteratively reweighted least squares (Tukey's biweight), the
  // scale from the residuals of the pixels within inlier_rel of the current plane.
  std::vector<double> weights(samples.size()), residuals(samples.size()), near;
  for (int it = 0; it < params.iterations; ++it) {
    near.clear();
    for (size_t i = 0; i < samples.size(); ++i) {
      residuals[i] = residual(abc, samples[i]);
      if (residuals[i] < params.inlier_rel * samples[i].z) near.push_back(residuals[i]);
    }
    if (near.size() < 3) {
      out.reason = "no plane agrees with the depth image";
      return out;
    }
    // A floor of 1 mm keeps an exact plane from dividing by zero.
    const double c = 4.685 * std::max(kMadToSigma * median(std::move(near)), 1e-3);
    Eigen::Matrix3d A = Eigen::Matrix3d::Zero();
    Eigen::Vector3d b = Eigen::Vector3d::Zero();
    for (size_t i = 0; i < samples.size(); ++i) {
      const double r = residuals[i] / c;
      weights[i] = r < 1 ? (1 - r * r) * (1 - r * r) : 0;
      if (weights[i] == 0) continue;
      const Eigen::Vector3d row(samples[i].x, samples[i].y, 1);
      A.noalias() += weights[i] * row * row.transpose();
      b += weights[i] * samples[i].z * row;
    }
    const Eigen::LDLT<Eigen::Matrix3d> ldlt(A);
    if (ldlt.info() != Eigen::Success || !(std::abs(A.determinant()) > 1e-12)) {
      out.reason = "the depth image spans no plane";
      return out;
    }
    abc = ldlt.solve(b);
  }
  size_t inliers = 0;
  double central_sum = 0;
  int central_count = 0;
  for (size_t i = 0; i < samples.size(); ++i) {
    if (weights[i] == 0) continue;
    ++inliers;
    if (samples[i].central) {
      central_sum += samples[i].z;
      ++central_count;
    }
  }
  if (central_count == 0) {
    out.reason = "no depth on the net in the central window";
    return out;
  }
  out.inlier_share = static_cast<double>(inliers) / static_cast<double>(samples.size());
  out.reason.clear();
  const NetAngles angles = net_angles_from_plane_C(abc.x(), abc.y());
  out.psi_net_rad = angles.psi_rad;
  out.pitch_net_rad = angles.pitch_rad;
  out.d_net_m = central_sum / central_count;
  return out;
}

}  // namespace pensight
