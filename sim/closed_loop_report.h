#pragma once
// What a closed-loop run is judged by, and its files: OUT/closed_loop.csv (contract 1.1: truth,
// estimates, references and commands per step, named columns) and OUT/closed_loop.html (one
// self-contained page of plots). docs/control.md.
#include <filesystem>
#include <vector>

#include "sim/closed_loop.h"

namespace pensight::sim {

struct LegMetrics {
  int leg = 0;
  double start_s = 0;
  double d_ref_m = 0;
  double step_m = 0;  // d_ref minus the true distance at the leg's start
  // From the leg's start until the distance error stays within max(5 cm, 10 % of the step);
  // NaN when it never does.
  double settle_s = kNaN;
  double overshoot_m = 0;  // beyond the reference, in the step's direction
};

struct ClosedLoopMetrics {
  // Over tracking steps at least settle_s into their leg: true distance (camera to net) and true
  // net-relative heading against the references.
  double distance_rmse_m = kNaN, heading_rmse_deg = kNaN;
  int settled_steps = 0;
  double min_distance_m = kNaN;  // the camera's nearest true distance to the net, whole run
  std::vector<LegMetrics> legs;
};

ClosedLoopMetrics closed_loop_metrics(const std::vector<ClosedLoopStep>& steps,
                                      double settle_s = 10.0);

// Written whole (temporary name, then rename); throws pensight::Error when `file` cannot be
// written.
void write_closed_loop_csv(const std::filesystem::path& file,
                           const std::vector<ClosedLoopStep>& steps);
void write_closed_loop_html(const std::filesystem::path& file, const Scenario& s,
                            const ClosedLoopSummary& summary);

}  // namespace pensight::sim
