#include "core/device_clock.h"

#include <cmath>

#include "core/units.h"

namespace pensight {
namespace {

const Param<DeviceClockParams> kDeviceClockParams[] = {
    {"window_s", &DeviceClockParams::window_s, "s", kPositive,
     "the offset is the smallest arrival - device time over this long"},
    {"max_jump_s", &DeviceClockParams::max_jump_s, "s", kPositive,
     "the offset falling by more at once: the device's clock was set"},
};

}  // namespace

std::span<const Param<DeviceClockParams>> device_clock_params() {
  return kDeviceClockParams;
}

DeviceClock::DeviceClock(DeviceClockParams params) : params_(params) {
  check_params<DeviceClockParams>(params_, kDeviceClockParams, "device clock");
}

int64_t DeviceClock::to_host_ns(int64_t device_ns, int64_t arrival_ns) {
  const int64_t offset = arrival_ns - device_ns;
  // A late sample (a stalled link) only has a larger offset and is mapped by the window's; a
  // clock set forward gives a smaller one, a clock set back a device time that goes back.
  const bool jumped =
      started_ && (device_ns < last_device_ns_ ||
                   offset < candidates_.front().second - seconds_to_ns(params_.max_jump_s));
  if (jumped) {
    candidates_.clear();
    ++resets_;
  }
  started_ = true;
  last_device_ns_ = device_ns;
  // A newer sample with a smaller offset makes the older, larger ones no longer candidates.
  while (!candidates_.empty() && candidates_.back().second >= offset) candidates_.pop_back();
  candidates_.emplace_back(arrival_ns, offset);
  const int64_t window_ns = seconds_to_ns(params_.window_s);
  while (candidates_.front().first < arrival_ns - window_ns) candidates_.pop_front();
  return device_ns + candidates_.front().second;
}

}  // namespace pensight
