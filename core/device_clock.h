#pragma once
// A device's clock (a DVL's, a camera's, an autopilot's boot time) mapped to the host's: every
// sample arrives at device time + offset + a transport delay >= 0, so the smallest
// (arrival - device time) over the last window_s is the offset plus the delay's floor, and the
// sample's host time is its device time plus that. The floor (a serial frame, a TCP segment: well
// under a millisecond to a few) is the error that remains; the jitter above it is removed. A
// device clock drifting by r (a crystal: 20-100 ppm) moves the offset by r x window_s within a
// window (0.5 ms at 50 ppm over 10 s), which the sliding minimum follows.
//
// A device time that goes back, or an offset more than max_jump_s below the window's (the device
// restarted, its clock was set), starts the window again (counted in resets()); a sample that
// arrives late (a stalled link) is mapped by the window's offset.
// Cost: amortised O(1) per sample, memory O(samples in a window).
#include <cstdint>
#include <deque>
#include <span>
#include <string>
#include <utility>

#include "core/params.h"

namespace pensight {

struct DeviceClockParams {
  double window_s = 10.0;   // the offset is the smallest seen over this long
  double max_jump_s = 1.0;  // the offset falling by more at once: the device's clock was set
};

// Key, unit, valid range and help of every DeviceClockParams member.
std::span<const Param<DeviceClockParams>> device_clock_params();

class DeviceClock {
 public:
  // Throws pensight::Error naming the key when a parameter is out of its range.
  explicit DeviceClock(DeviceClockParams params = {});

  // The host time of a sample stamped `device_ns` by the device and received at `arrival_ns` on
  // the host clock; samples are given in arrival order.
  int64_t to_host_ns(int64_t device_ns, int64_t arrival_ns);
  int resets() const { return resets_; }

 private:
  DeviceClockParams params_;
  // (arrival, arrival - device) of the window's samples whose offset is a candidate minimum:
  // increasing in both, the front the smallest.
  std::deque<std::pair<int64_t, int64_t>> candidates_;
  int64_t last_device_ns_ = 0;
  bool started_ = false;
  int resets_ = 0;
};

}  // namespace pensight
