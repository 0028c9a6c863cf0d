#pragma once
// Net texture odometry: how far the net point seen at the image centre moved over the net between
// two frames, counted in the net's own bars. The lattice's phase at the centre pixel is that
// point's position within its mesh cell (mod one bar, per bar direction); the phase change
// between consecutive frames is the point's move in bars, known up to whole bars, which the
// global-pose estimator resolves with its own prediction (global_pose_estimator.h).
//
// Method: the complex Fourier coefficient of a Hann-windowed patch centred on the pixel at the
// lattice's reciprocal vectors (the duals of the image bars), in both frames at the later frame's
// frequencies; a symmetric window makes the coefficient's phase the phase at its centre even where
// perspective bends the lattice (phase correlation at known frequencies, Kuglin and Hines 1975).
// Cost: two 1-D passes per frame and frequency over the patch, 4 x 256^2 complex multiply-adds
// per frame (~0.3 ms on one core).
#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <vector>

#include "core/camera.h"
#include "core/image.h"
#include "pipeline/fft/net_geometry.h"
#include "pipeline/fft/relative_pose_fft.h"

namespace pensight {

struct NetTextureParams {
  bool enabled = true;
  int window_px = 256;  // side of the patch about the image centre
  // The nearest valid ROI's centre must lie within this share of the window's side from the
  // patch centre, so that its bars are the lattice the patch holds.
  double max_roi_offset_share = 0.5;
  // The coefficient's magnitude over the patch's windowed contrast (RMS): below it the patch
  // holds no clear lattice at that frequency (open water, blur, fouling).
  double min_coherence = 0.05;
};

// One frame's patch: grey values about the centre pixel, zero-mean under the window.
struct TexturePatch {
  int64_t t_ns = 0;
  Eigen::Vector2d centre_px = Eigen::Vector2d::Zero();
  Eigen::Vector2i first_px = Eigen::Vector2i::Zero();  // the image pixel of pixels[0]
  int size_px = 0;
  std::vector<float> pixels;  // row-major size_px^2, windowed, zero weighted mean
  double rms = 0;             // of the windowed pixels
  bool valid() const { return size_px > 0; }
};

// The patch about the image's principal point; empty (size 0) when the window does not fit.
TexturePatch texture_patch(const ImageU8& image, const PinholeCamera& camera, int64_t t_ns,
                           const NetTextureParams& params);

// The move of the centre ray's net point from `from` to the current frame, in bars.
struct TextureStep {
  bool valid = false;
  int64_t from_ns = 0;
  // Per bar: the move in bars, wrapped to [-0.5, 0.5) (whole bars are not observable).
  std::array<double, 2> moved_bars{};
  // The two bars on the net in C [m], each of the mesh's bar length: the move in metres is
  // sum_i (moved_bars[i] + k_i) bars_C[i] for the right whole numbers k_i.
  std::array<Eigen::Vector3d, 2> bars_C{};
  Eigen::Vector3d ray_C = Eigen::Vector3d::UnitZ();  // the centre pixel's ray (z = 1)
};

// Precondition: bar_length_m > 0. Returns valid = false when either patch is empty, the frame's
// pose is not valid, no valid ROI lies near the patch centre, or the lattice is not coherent in
// both patches (params.min_coherence).
TextureStep texture_step(const TexturePatch& from, const TexturePatch& to,
                         const std::vector<RoiNetPoint>& points, const FftRelativePose& pose,
                         const PinholeCamera& camera, double bar_length_m,
                         const NetTextureParams& params);

}  // namespace pensight
