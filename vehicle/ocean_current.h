#pragma once
// Ocean current in the pen frame: the mean plus a first-order Gauss-Markov process on x and y,
// v_dot = -v / T + w (Fossen 2011, ch. 8), updated exactly for each step so its stationary
// standard deviation stays variation_mps at any step. Seeded: the same params give the same run.
#include <Eigen/Core>
#include <random>

#include "vehicle/bluerov2_params.h"

namespace pensight::vehicle {

class OceanCurrent {
 public:
  // Precondition: check_params() accepted the current. Starts from a stationary draw.
  explicit OceanCurrent(const CurrentParams& params);

  Eigen::Vector3d velocity_pen_mps() const { return params_.mean_pen_mps + variation_pen_mps_; }

  // Moves the variation on by dt_s (two normal draws).
  void advance(double dt_s);

 private:
  CurrentParams params_;
  std::mt19937_64 rng_;
  Eigen::Vector3d variation_pen_mps_ = Eigen::Vector3d::Zero();
};

}  // namespace pensight::vehicle
