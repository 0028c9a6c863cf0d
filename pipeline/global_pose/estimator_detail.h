#pragma once
// Shared by the files of GlobalPoseEstimator (global_pose_estimator.cpp: the replay buffer;
// estimator_sensor_models.cpp; estimator_gating.cpp; estimator_initialisation.cpp), not part of
// its interface.
#include <Eigen/Core>
#include <array>
#include <span>
#include <string>

#include "core/units.h"
#include "pipeline/global_pose/global_pose_estimator.h"

namespace pensight::global_pose::detail {

enum Sensor : int {
  kDvlVelocity,
  kDvlPlane,
  kDepthSensor,
  kAttitudeYaw,
  kVisionFix,
  kVisionRel,
  kNetTexture
};

enum Warning : int {
  kWarnNoAttitudeAt,
  kWarnInvalidDvl,
  kWarnInvalidDepth,
  kWarnFixFailed,
  kWarnRejected,
  kWarnRelock,
  kWarnOutOfOrder,
  kWarnDuplicate,
  kWarnTooLate,
  kWarnNotLockable,
  kWarnDvlSpike,
};

inline const char* sensor_name(int s) {
  static const char* names[] = {"DVL velocity", "DVL plane",        "pressure depth",
                                "attitude yaw", "vision r_g/psi_r", "vision d_net/psi_net",
                                "net texture"};
  return names[s];
}

// The states each measurement model reads (a vertical cylinder does not depend on depth).
inline constexpr int kPoseStates[] = {kX, kY, kPsi};
inline constexpr int kVisionStates[] = {kX, kY, kPsi, kFixHeadingBias};
inline constexpr int kVelocityStates[] = {kU, kV, kW, kDvlBiasU, kDvlBiasV};
inline constexpr int kDepthStates[] = {kZ};
inline constexpr int kYawStates[] = {kPsi, kYawBias};
inline constexpr int kPoseStates3D[] = {kX, kY, kZ, kPsi};
inline constexpr int kTextureStates[] = {kX, kY, kZ, kPsi, kNetTextureOffset};

template <int M>
Eigen::Matrix<double, M, M> diag(const Eigen::Matrix<double, M, 1>& sigma) {
  return sigma.cwiseAbs2().asDiagonal();
}

}  // namespace pensight::global_pose::detail

namespace pensight::global_pose {

template <int M, class H>
UpdateOutcome GlobalPoseEstimator::gated_update(int sensor, SensorCounters& c,
                                                const Eigen::Matrix<double, M, 1>& z, H&& h,
                                                const Eigen::Matrix<double, M, M>& R,
                                                std::array<bool, M> angles,
                                                std::span<const int> depends_on) {
  using namespace detail;
  int& streak = state_.consecutive_rejections[static_cast<size_t>(sensor)];
  const bool motion = sensor == kDvlVelocity || sensor == kAttitudeYaw || sensor == kDepthSensor;
  const bool relock =
      streak >= (motion ? cfg_.motion_relock_after_rejections : cfg_.relock_after_rejections);
  const double gate = cfg_.gate_scale * kGateChi2[M];
  // A motion sensor's sample is first tried with the gate: only one that still fails it after
  // the streak means the motion changed.
  bool ungated = relock && !motion;
  UpdateOutcome outcome = state_.ekf.update<M>(z, h, R, angles, depends_on, ungated ? 0.0 : gate);
  if (relock && motion && outcome == UpdateOutcome::kRejected) {
    release_motion_states(sensor);
    ungated = true;
    outcome = state_.ekf.update<M>(z, h, R, angles, depends_on, 0.0);
  }
  switch (outcome) {
    case UpdateOutcome::kAccepted:
      ++c.accepted;
      if (sensor == kDvlVelocity || sensor == kAttitudeYaw)
        state_.last_rho_aid_ns = state_.ekf.t_ns;
      if (ungated) {
        ++c.relocked;
        warn_once(kWarnRelock, std::string(sensor_name(sensor)) +
                                   " rejected repeatedly; applied without the gate to re-lock");
      }
      streak = 0;
      break;
    case UpdateOutcome::kRejected:
      ++c.rejected;
      ++streak;
      warn_once(kWarnRejected,
                std::string(sensor_name(sensor)) + " sample rejected by the innovation gate");
      break;
    case UpdateOutcome::kSkipped:
      ++c.invalid;
      break;
  }
  return outcome;
}

}  // namespace pensight::global_pose
