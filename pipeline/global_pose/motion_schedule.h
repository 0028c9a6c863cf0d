#pragma once
// Which spans between DVL samples the vehicle moved quietly, for the process noise of the
// horizontal velocity (noise-level switching: Bar-Shalom, Li and Kirubarajan, "Estimation with
// Applications to Tracking and Navigation", 2001, sec. 11.2-11.3, with the manoeuvre detected
// from the DVL and the filter restarted from the start of the detected span, as in Bar-Shalom
// and Birmiwal's variable-dimension filter, IEEE Trans. AES 18(5), 1982).
//
// A white-acceleration model leaves the position between two velocity samples uncertain by
// q dt^3 / 12: at the 0.5 m/s^2/sqrt(Hz) an ROV's manoeuvres need, 1.8 cm per 4 Hz DVL interval,
// so the DVL's integral barely carries and the along-net position follows the absolute heading
// aids instead. Following the net, consecutive DVL samples differ by little more than their
// noise: there, once they have been so for settle_s, the quiet noise applies. A span whose two
// samples differ by more than an ROV's acceleration in net-pen work
// (DvlSpikeTestOptions::max_accel_mps2, the bound the spike test starts from) is a manoeuvre
// and gets the manoeuvring noise; so do spans no pair of samples vouches for (before the first,
// across gaps, after the DVL stops).
//
// Between samples the span is not yet known: it is taken as quiet when the last one was, until
// the next sample is overdue (the spike test may be holding it). When the next sample shows
// otherwise the filter re-applies from the span's start (add() says from when). Cost: a map
// look-up per prediction; a re-apply at the start and the end of each manoeuvre and after each
// spike.
#include <Eigen/Core>
#include <cstdint>
#include <limits>
#include <map>
#include <optional>

#include "pipeline/global_pose/dvl_spike_test.h"

namespace pensight::global_pose {

class MotionSchedule {
 public:
  // Quiet spans begin once the samples have stayed within the bound for settle_s: a manoeuvre
  // can pass its peak speed, or turn, with two samples alike.
  explicit MotionSchedule(DvlSpikeTestOptions o = {}, double settle_s = 1.0)
      : o_(o), settle_s_(settle_s) {}

  // Notes an accepted (not spiked) DVL sample with its pen-frame velocity, in time order (an
  // older one is ignored). Returns the start of its span when the span was predicted, in part or
  // whole, with the other process noise: everything applied after that time must be applied
  // again.
  std::optional<int64_t> add(int64_t t_ns, const Eigen::Vector3d& velocity_pen_mps);
  // Whether the prediction from t0_ns to t1_ns lies in one quiet span.
  bool quiet(int64_t t0_ns, int64_t t1_ns) const;
  // Forgets spans that ended before t_ns (the latest is kept).
  void trim_before(int64_t t_ns);

 private:
  struct Span {
    int64_t start_ns = 0;
    bool quiet = false;
  };
  // When the sample after the one ending `span` at end_ns is due: 1.5 intervals later.
  static int64_t due_ns(int64_t end_ns, const Span& span);
  static constexpr int64_t kNotCalm = std::numeric_limits<int64_t>::max();
  DvlSpikeTestOptions o_;
  double settle_s_ = 1.0;
  int64_t calm_since_ns_ = kNotCalm;  // start of the samples within the bound, up to the latest
  std::map<int64_t, Span> spans_;     // by the time of the sample that ends the span
  Eigen::Vector3d last_velocity_pen_mps_ = Eigen::Vector3d::Zero();
};

}  // namespace pensight::global_pose
