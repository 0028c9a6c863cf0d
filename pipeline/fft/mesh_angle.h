#pragma once
// The net's opening angle from a whole frame. One ROI cannot tell a sheared cell from a tilted
// square (net_geometry.h), but a frame can: the plane through the ROIs' net points fixes the net's
// tilt from their ranges alone, and each ROI's lattice back-projected onto that plane gives its
// two bars in metres, whose angle is the opening angle. Both the range and the plane's slopes
// depend only weakly on the angle assumed for them, so two rounds of angle -> points -> plane ->
// angle converge (NetDetector).
//
// The angle reported is the cell's angle bisected by a reference direction in the net plane:
// for a diamond mesh the net's vertical (bars at +-angle/2 from it), for a square mesh the
// diagonal between the net's right and up (bars along the right and at the angle from it). The
// net's up is the camera's up (-y_C) projected onto the plane: vehicles hold roll near 0.
// Measured that way the angle is continuous through 90 deg, so noise averages out instead of
// folding onto the acute side.
#include <Eigen/Core>
#include <cstdint>
#include <optional>
#include <span>

#include "core/camera.h"
#include "core/dataset_types.h"
#include "pipeline/fft/net_geometry.h"

namespace pensight {

struct MeshAngleParams {
  // A ROI whose two bars on the plane differ in length by more than this share is no rhombus
  // cell (an unreduced harmonic, a lattice of two nets): left out.
  double max_bar_mismatch = 0.15;
  int min_rois = 4;
  // Bisector within this angle of the net's vertical or horizontal: a diamond mesh (a square
  // mesh's bisectors lie near 45 deg; the two meet at 22.5 deg).
  double diamond_bisector_rad = 0.3927;
  // A frame whose median bisector lies this far or further from diamond_bisector_rad shows its
  // type whatever the type given: a diamond's bisector within 14.5 deg of the vertical (roll
  // included), a square's cell up to about 119 deg. Nearer, the given type decides.
  double type_evidence_margin_rad = 0.14;  // 8 deg
};

struct MeshAngleMeasurement {
  double opening_angle_rad = kNaN;    // per the mesh type's reference (above)
  double sigma_rad = kNaN;            // of the median, from the ROIs' spread
  MeshType type = MeshType::kSquare;  // the given type, else the one the bisectors show
  int rois = 0;                       // ROIs that measured it
  bool valid() const { return rois > 0; }
};

// Precondition: normals_C holds, per ROI, the net's unit normal in C where the ROI sees it (the
// plane's, or a curved wall's there: FftRelativePose::surface_C; a diamond's angle read on the
// plane of a 12 m wall 2.5 m away opens by 0.8 deg at the sides). `use`: per ROI, 1 where the
// ROI is on the net (FftRelativePose::inlier). `type`: the mesh type expected (scene.yaml), a
// prior: it decides where the bisectors do not, and a frame that clearly shows the other type (a
// diamond section of a square net, another pen) is measured as what it shows. A square-type
// reference on a diamond cell lies halfway between its two angles, so each ROI would pick either.
// Fewer than min_rois usable ROIs: an invalid measurement. Cost: two ray casts per bar per ROI.
MeshAngleMeasurement measure_mesh_angle(std::span<const RoiNetPoint> rois,
                                        std::span<const uint8_t> use,
                                        std::span<const Eigen::Vector3d> normals_C,
                                        const PinholeCamera& camera, std::optional<MeshType> type,
                                        const MeshAngleParams& params = {});

// The opening angle smoothed over frames: a scalar Kalman filter with a random walk of
// process_sigma_rad per frame, a prior (scene.yaml's nominal angle) or none, and a restart on
// a measurement that stays far outside its gate (a different net).
class MeshAngleFilter {
 public:
  struct Params {
    double process_sigma_rad = 0.005;  // 0.3 deg per frame: currents deform a net slowly
    double prior_sigma_rad = 0.17;     // 10 deg: a hung net shears well away from nominal
    double min_sigma_rad = 0.002;      // a frame's own floor (the lattice's sub-bin precision)
    double gate_sigmas = 4;
    int restart_after = 3;  // consecutive frames outside the gate
  };
  explicit MeshAngleFilter(std::optional<double> prior_rad);
  MeshAngleFilter(std::optional<double> prior_rad, const Params& params);

  // The estimate to model this frame's ROIs with: the filtered angle, else the prior, else 90 deg.
  double angle_rad() const;
  bool has_estimate() const { return state_.var >= 0; }
  // Fuses one frame's measurement (an invalid one only lets the estimate drift); returns
  // angle_rad().
  double update(const MeshAngleMeasurement& m);
  // Replaces the last update's measurement by a better one of the same frame; returns
  // angle_rad().
  double refine(const MeshAngleMeasurement& m);
  // The last update's or refine's measurement fell outside the gate and was not fused: the frame
  // disagrees with the carried angle (NetDetector then solves it on its own).
  bool rejected_last() const { return rejected_last_; }

 private:
  struct State {
    double angle = 0;
    double var = -1;  // < 0: nothing yet
    int outside = 0;
  };
  void fuse(const MeshAngleMeasurement& m);
  Params params_;
  State state_, before_;
  bool rejected_last_ = false;
};

}  // namespace pensight
