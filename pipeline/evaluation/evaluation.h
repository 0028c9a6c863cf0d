#pragma once
// Scores estimates (OUT/estimates.csv rows) against a dataset's groundtruth0, as the issues
// state their acceptance: errors over the frames inside an envelope (net fills the image, range
// and heading within limits), and the share of all frames that report a grossly wrong distance.
#include <cstddef>
#include <span>
#include <string>

#include "pipeline/dataset/dataset_reader.h"
#include "pipeline/dataset/estimates_csv.h"

namespace pensight {

// Frames whose truth lies inside these limits are "measurable" and count for the error figures.
struct AccuracyEnvelope {
  double min_net_fraction = 0.5;
  double min_d_net_m = 0.4;
  double max_d_net_m = 2.5;
  double max_abs_psi_net_rad = 35.0 * 3.14159265358979323846 / 180.0;
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

}  // namespace pensight
