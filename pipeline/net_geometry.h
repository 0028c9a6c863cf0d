#pragma once
// From one ROI's two base frequency vectors to a point on the net: the image lattice vectors are
// the dual of the frequency vectors; one net square of known mesh size seen through the camera
// (distortion included) gives the range along the ROI's centre ray in closed form, the tilt of the
// net against that ray, and the 3D centre point in the camera frame C.
//
// Closed form: rotate the camera virtually so that the centre ray becomes the optical axis. There
// the square's image is, to first order, (mesh / range) times the top two rows of a 3x2 matrix
// with orthonormal columns, whose largest singular value is 1 and smallest cos(tilt). So
// range = mesh / sigma_max(lattice in the rotated normalised image) and
// tilt = acos(sigma_min / sigma_max). The tilt's sign is not observable from one ROI (the affine
// image of a square is the same for +/- tilt); both normals are returned and the frame-level
// plane fit (relative_pose_fft.h) settles it from many ROIs.
#include <Eigen/Core>
#include <array>
#include <string>
#include <vector>

#include "kernels/fft_roi/fft_roi.h"
#include "pipeline/camera.h"

namespace pensight {

struct NetPointParams {
  double min_quality = 0.03;   // share of spectral energy in the lattice peaks
  double min_period_px = 2.5;  // finer lattices are below what the resampled ROI can carry
  double max_tilt_rad = 1.22;  // 70 deg: beyond, the foreshortened period is unreliable
  double max_range_m = 20.0;
  bool use_centroid = true;  // place the point at the ROI's energy centroid (off: ROI centre)
  // A lattice whose energy centroid lies further than this share of the ROI size from its centre
  // covers only part of the ROI (net edge, occlusion): its peak is skewed by the truncation.
  double max_centroid_share = 0.05;
};

enum class RoiStatus { kValid, kNoLattice, kPartial, kTooFine, kTooOblique, kBadGeometry };
const char* to_string(RoiStatus status);

struct RoiNetPoint {
  RoiStatus status = RoiStatus::kNoLattice;
  Eigen::Vector2d centre_px = Eigen::Vector2d::Zero();    // ROI centre + energy centroid offset
  Eigen::Vector2d lattice1_px = Eigen::Vector2d::Zero();  // image lattice vectors at the centre
  Eigen::Vector2d lattice2_px = Eigen::Vector2d::Zero();
  Eigen::Vector3d p_C = Eigen::Vector3d::Zero();  // net point on the centre ray, camera frame
  double range_m = 0;                             // |p_C|
  double tilt_rad = 0;                            // between the net normal and the centre ray
  std::array<Eigen::Vector3d, 2> normals_C{};     // the two normal candidates (+z_C pointing)
  double quality = 0;
  bool valid() const { return status == RoiStatus::kValid; }
};

// Sparse depth sample for the depth-completion stage: pixel and z-depth in C.
struct SparseDepth {
  float px = 0, py = 0;
  float depth_m = 0;
  float quality = 0;
};

// Precondition: mesh_m > 0 (throws pensight::Error otherwise). A ROI without a usable lattice
// comes back with its status set and p_C zero, never an exception.
RoiNetPoint roi_net_point(const kernels::RoiLattice& lattice, kernels::RoiOrigin origin,
                          int roi_size, const PinholeCamera& camera, double mesh_m,
                          const NetPointParams& params = {});

}  // namespace pensight
