#pragma once
// Scores estimates (OUT/estimates.csv rows) against a dataset's groundtruth0, as the issues
// state their acceptance: errors over the frames inside an envelope (net fills the image, range
// and heading within limits), and the share of all frames that report a grossly wrong distance.
#include <cstddef>
#include <cstdint>
#include <span>
#include <string>

#include "core/dataset_types.h"
#include "core/units.h"
#include "pipeline/dataset/dataset_reader.h"
#include "pipeline/dataset/estimates_csv.h"

namespace pensight {

// Frames whose truth lies inside these limits are "measurable" and count for the error figures.
struct AccuracyEnvelope {
  double min_net_fraction = 0.5;
  double min_d_net_m = 0.4;
  double max_d_net_m = 2.5;
  double max_abs_psi_net_rad = deg_to_rad(35.0);
};

struct ErrorStats {
  size_t count = 0;
  double median = 0;
  double p95 = 0;
  double max = 0;
};
// Median, 95th percentile (nearest rank) and maximum of |errors|; count 0 when empty.
ErrorStats error_stats(std::span<const double> errors);

struct NetPoseAccuracy {
  size_t frames = 0;                // rows scored (those with a ground-truth row)
  size_t measurable = 0;            // inside the envelope
  size_t measurable_estimated = 0;  // of those, with a finite estimate
  ErrorStats d_net_rel;             // |d - d_true| / d_true, measurable frames with an estimate
  ErrorStats psi_net_deg;
  ErrorStats pitch_net_deg;
  // Frames (of all scored) reporting a distance more than gross_rel off the truth, or a distance
  // where the optical axis misses the net.
  size_t gross_errors = 0;
  double gross_rel = 0.2;
};

enum class NetPoseSource { kFft, kDepth };

// Throws pensight::Error when the dataset has no groundtruth0.
NetPoseAccuracy score_net_pose(const Dataset& dataset, std::span<const EstimateRow> rows,
                               NetPoseSource source, const AccuracyEnvelope& envelope = {});

// Human-readable lines for the report, e.g. "d_net rel. error: median 0.41%, p95 1.2% (n=87)".
std::string describe(const NetPoseAccuracy& a);

// Global pose (r_g, rho_g, z_g, psi_g) against the truth body pose: r = hypot(x, y), z, and, as
// dataset-format.md says the pen's azimuth origin is not observable, rho = atan2(y, x) and
// psi = yaw compared as changes from the reference frame (the first scored frame where rho_g
// and psi_g are finite). Angle differences are wrapped to (-pi, pi]. Every scored frame counts,
// whatever its distance from the net.
struct GlobalPoseAccuracy {
  size_t frames = 0;                    // rows scored (those with a ground-truth row)
  size_t with_r_g = 0;                  // of those, with a finite r_g
  size_t with_z_g = 0;                  // ... z_g
  size_t with_rho_psi = 0;              // ... rho_g and psi_g
  ErrorStats r_g_m;                     // r_g - r_true
  ErrorStats z_g_m;                     // z_g - z_true
  ErrorStats rho_change_deg;            // (rho_g - rho_g at ref) - (rho_true - rho_true at ref)
  ErrorStats psi_change_deg;            // same for psi_g against yaw
  int64_t reference_timestamp_ns = -1;  // -1: no frame with rho_g and psi_g
  double path_m = 0;                    // horizontal path of the truth from the reference frame
  double rho_drift_per_m = kNaN;        // rho_drift_per_m() over the scored frames
};

// rho_g drift per metre travelled (docs/global_pose.md): |mean arc error over the last window_s
// seconds| / path_m, the arc error of a frame being its rho change error (rad) times the true r.
// t_s and arc_error_m are per frame, in time order. NaN without frames or path.
double rho_drift_per_m(std::span<const double> t_s, std::span<const double> arc_error_m,
                       double path_m, double window_s = 5.0);

// Throws pensight::Error when the dataset has no groundtruth0.
GlobalPoseAccuracy score_global_pose(const Dataset& dataset, std::span<const EstimateRow> rows);

std::string describe(const GlobalPoseAccuracy& a);

}  // namespace pensight
