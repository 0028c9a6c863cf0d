#pragma once
// How far the stages after the FFT detector trust its net-relative pose, from the pose's quality
// (FftRelativePose::quality, pipeline/fft/relative_pose_fft.h): in core because the global pose
// and the controller, in layers that do not see each other, read it the same way.
#include <algorithm>

namespace pensight {

// The quality above which an FFT pose's d_net error stops shrinking: on rendered frames with truth
// (docs/validation-log.md) its rms is 0.27 % above 0.5, 0.54 % at 0.3-0.4, 0.8 % at 0.1-0.3,
// 1.8 % at 0.05-0.1 and 2.9 % below 0.05, close to 1 / quality.
inline constexpr double kFullTrustPoseQuality = 0.5;

// The trust in a pose of this quality, in [0.1, 1]: quality / kFullTrustPoseQuality, at most 1; at
// least 0.1, below which the error no longer grows as 1 / quality. The global pose divides the
// pose's variance by it; the controller moves its net estimate that share of the way to the pose.
inline double pose_trust(double quality) {
  return std::clamp(quality / kFullTrustPoseQuality, 0.1, 1.0);
}

}  // namespace pensight
