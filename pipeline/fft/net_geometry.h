#pragma once
// From one ROI's two base frequency vectors to a point on the net: the image lattice vectors are
// the dual of the frequency vectors; one net cell (a rhombus of two bars of known length meeting
// at the opening angle) seen through the camera (distortion included) gives the range along the
// ROI's centre ray in closed form, the tilt of the net against that ray, and the 3D centre point
// in the camera frame C.
//
// Basis: the spectrum's two strongest peaks need not be the bars' (a knot pattern puts a peak on
// the cell's diagonal, f1 + f2); any two independent peaks of the lattice span it, so the image
// lattice basis is Lagrange-Gauss reduced to its shortest pair, which for opening angles of
// 60-120 deg are the bars.
//
// Closed form: rotate the camera virtually so that the centre ray becomes the optical axis. There
// the cell's image is, to first order, (bar / range) J R M0 with J the top two rows of a 3x2
// matrix with orthonormal columns (the net plane's axes), R an unknown in-plane rotation and
// M0 = [1 cos(a); 0 sin(a)] the cell of opening angle a. So with B the lattice in the rotated
// normalised image, range = bar / sigma_max(B M0^-1) and tilt = acos(sigma_min / sigma_max)
// (a = 90 deg: a square). The tilt's sign is not observable from one ROI (the affine image of a
// cell is the same for +/- tilt); both normals are returned and the frame-level plane fit
// (relative_pose_fft.h) settles it from many ROIs. The opening angle itself is not observable
// from one ROI either (4 numbers, 5 unknowns): mesh_angle.h estimates it from the whole frame.
#include <Eigen/Core>
#include <array>
#include <numbers>
#include <string>
#include <vector>

#include "core/camera.h"
#include "kernels/fft_roi/fft_roi.h"
#include "kernels/sparse_prior/sparse_prior.h"

namespace pensight {

// The net cell as the closed form models it.
struct MeshModel {
  double bar_length_m = 0.030;  // knot to knot (scene.yaml net_mesh_size_m)
  // Either angle of the rhombus: a and pi - a describe the same cell.
  double opening_angle_rad = std::numbers::pi / 2;
};

struct NetPointParams {
  double min_quality = 0.03;  // share of spectral energy in the lattice peaks
  // Illumination gradients (a light cone, backscatter) leak through the window into the band's
  // lowest frequencies, and there open water reaches min_quality (0.038 at 5 cycles, a 0.16 m net
  // read in a frame with no net). A net that near fills the ROI with thick, bright twines: rendered
  // and real lattices under 8 cycles hold >= 0.12 of the energy. So a lattice with a base vector
  // under near_cycles needs near_min_quality.
  double near_cycles = 8.0;
  double near_min_quality = 0.06;
  double min_period_px = 2.5;  // finer lattices are below what the resampled ROI can carry
  double max_tilt_rad = 1.22;  // 70 deg: beyond, the foreshortened period is unreliable
  double max_range_m = 20.0;
  bool use_centroid = true;  // place the point at the ROI's energy centroid (off: ROI centre)
  // A lattice whose energy centroid lies further than this share of the ROI size from its centre
  // covers only part of the ROI (net edge, occlusion): its peak is skewed by the truncation. A full
  // net moves the centroid too: a rope or seam in the ROI (its contrast energy on one side) and an
  // oblique view (the nearer side coarser and brighter) by 15-25 px of 300 on rendered frames, so
  // the limit sits above that; 5 % refused most of those ROIs (docs/fft_detection.md).
  double max_centroid_share = 0.075;
};

enum class RoiStatus { kValid, kNoLattice, kPartial, kTooFine, kTooOblique, kBadGeometry };
const char* to_string(RoiStatus status);

struct RoiNetPoint {
  RoiStatus status = RoiStatus::kNoLattice;
  kernels::RoiOrigin origin;  // the ROI's top-left pixel: a grid column's ROIs share its x
  Eigen::Vector2d centre_px = Eigen::Vector2d::Zero();  // ROI centre + energy centroid offset
  // Image lattice vectors at the centre: the reduced basis (the bars), lattice2 signed so that the
  // two make the cell's acute angle on the net (per the normal hint, else in the image).
  Eigen::Vector2d lattice1_px = Eigen::Vector2d::Zero();
  Eigen::Vector2d lattice2_px = Eigen::Vector2d::Zero();
  bool reduced = false;  // the spectrum's basis held a diagonal and was reduced to the bars
  Eigen::Vector3d p_C = Eigen::Vector3d::Zero();  // net point on the centre ray, camera frame
  double range_m = 0;                             // |p_C|
  double tilt_rad = 0;                            // between the net normal and the centre ray
  // The two normal candidates (+z_C pointing); zero for a point without them.
  std::array<Eigen::Vector3d, 2> normals_C{Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero()};
  double quality = 0;
  bool valid() const { return status == RoiStatus::kValid; }
};

// Sparse depth sample for the depth-completion stage: the kernels' SparsePoint (here in the
// camera image's pixels; the depth stage scales it to the network input) and its quality.
struct SparseDepth {
  kernels::SparsePoint point;  // x_px, y_px, z-depth in C
  float quality = 0;
};

// Precondition: mesh.bar_length_m > 0 and an opening angle within (0, pi) (throws pensight::Error
// otherwise). A ROI without a usable lattice comes back with its status set and p_C zero, never
// an exception. `normal_hint_C` (a net normal in C, e.g. the frame's fitted plane) decides which
// pair of bars makes the acute angle; without it the image's angle does, which can pick the
// obtuse pair for a near-square cell seen obliquely (a range error of about |cos a|).
RoiNetPoint roi_net_point(const kernels::RoiLattice& lattice, kernels::RoiOrigin origin,
                          int roi_size_px, const PinholeCamera& camera, const MeshModel& mesh,
                          const NetPointParams& params = {},
                          const Eigen::Vector3d* normal_hint_C = nullptr);

// Where `ray` (C) meets the plane through point_C with normal normal_C; infinite or NaN where the
// ray is parallel to it, behind the camera where the plane is behind.
Eigen::Vector3d ray_on_plane(const Eigen::Vector3d& ray, const Eigen::Vector3d& point_C,
                             const Eigen::Vector3d& normal_C);

// The image lattice vectors' displacements on the plane through p_C with normal normal_C:
// the two bars in 3D (C, metres, up to the plane's scale when p_C is only a direction).
std::array<Eigen::Vector3d, 2> bars_on_plane(const RoiNetPoint& roi, const PinholeCamera& camera,
                                             const Eigen::Vector3d& point_C,
                                             const Eigen::Vector3d& normal_C);

}  // namespace pensight
