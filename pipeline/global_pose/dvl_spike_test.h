#pragma once
// Rejects DVL velocity spikes by what an ROV can do and by what a spike is. Between two samples
// the vehicle's velocity over the ground changes by at most max_accel x the interval (thrust over
// mass plus added mass; while the accepted samples show it accelerating harder, by that), so a
// sample farther than that, plus the sensor noise, from the last accepted one is suspect. A spike
// is short: it is confirmed when a later sample, within max_spike_samples, is back within the
// bound of the reference. A velocity that stays off is a manoeuvre beyond the bound (the
// synthetic sweep's turn-in reaches 5 m/s^2), and its samples are released, late, to be applied
// in time order. Velocities are compared in the pen frame (levelled, turned by the heading), so a
// fast turn, which rotates the body-frame velocity, is not taken for an acceleration.
// Cost: a comparison per sample; at most max_spike_samples samples are held.
#include <cstdint>
#include <vector>

#include <Eigen/Core>

#include "core/dataset_types.h"

namespace pensight::global_pose {

struct DvlSpikeTestOptions {
  // A BlueROV2 Heavy in net-pen work stays below this; a 0.3 m/s spike lasting two samples at
  // 4 Hz is still 0.05 m/s (10 x the noise of a difference) beyond it at the second sample.
  double max_accel_mps2 = 0.4;
  double noise_mps = 0.005;   // white velocity noise per axis of one sample
  double noise_sigmas = 4.0;  // margin on the difference of two samples' noise
  int max_spike_samples = 2;
  // Suspect samples with no later sample for this long are dropped as spikes (a dropout after a
  // spike leaves nothing to confirm a manoeuvre with).
  double max_hold_s = 1.0;
};

class DvlSpikeTest {
 public:
  explicit DvlSpikeTest(DvlSpikeTestOptions o = {}) : o_(o) {}

  // Takes a valid sample with its pen-frame velocity (samples in time order) and returns the
  // samples now known not to be spikes, oldest first: usually the sample itself; nothing while it
  // is suspect; the held ones too once the velocity stayed off.
  std::vector<DvlSample> push(const DvlSample& s, const Eigen::Vector3d& velocity_pen_mps);
  // Drops held samples older than max_hold_s before t_ns as spikes.
  void expire(int64_t t_ns);
  // Samples judged spikes so far.
  int spikes() const { return spikes_; }
  // The margin for noise on the difference of two samples (noise_sigmas of it, all axes).
  static double difference_noise_mps(const DvlSpikeTestOptions& o);

 private:
  bool within_bound(int64_t t_ns, const Eigen::Vector3d& v_pen) const;
  void set_reference(int64_t t_ns, const Eigen::Vector3d& v_pen);

  struct Held {
    DvlSample sample;
    Eigen::Vector3d velocity_pen_mps;
  };
  DvlSpikeTestOptions o_;
  bool have_reference_ = false;
  int64_t reference_ns_ = 0;
  Eigen::Vector3d reference_pen_mps_ = Eigen::Vector3d::Zero();
  double recent_accel_mps2_ = 0;
  std::vector<Held> held_;
  int spikes_ = 0;
};

}  // namespace pensight::global_pose
