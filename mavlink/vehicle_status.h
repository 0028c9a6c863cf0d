#pragma once
// What an ArduSub vehicle last said over MAVLink (VehicleLink::status()).
#include <array>
#include <cstdint>

#include "mavlink/messages.h"

namespace pensight::mavlink {

// What the target vehicle last said; a *_ns of -1: not heard yet. Times are poll()'s clock.
struct VehicleStatus {
  int64_t heartbeat_ns = -1;
  bool armed = false;
  uint32_t custom_mode = 0;  // the ArduSub mode number (SubMode)
  uint8_t system_status = 0;
  int64_t sys_status_ns = -1;
  SysStatus sys_status;  // battery, load, sensor health
  int64_t attitude_ns = -1;
  Attitude attitude;
  // SCALED_PRESSURE, SCALED_PRESSURE2, SCALED_PRESSURE3 (index 0-2), each the last heard.
  std::array<int64_t, 3> pressure_ns = {-1, -1, -1};
  int64_t first_pressure_ns = -1;  // the first of any barometer
  std::array<ScaledPressure, 3> pressure;
  // Each barometer's pressure averaged over about WaterDepthParams::smoothing_s (hPa), what the
  // automatic choice of the water's barometer compares (record_barometer, water_depth.h).
  std::array<double, 3> pressure_average_hpa = {0, 0, 0};
  int water_index = -1;  // the barometer chosen as the water's, -1: none yet
};

}  // namespace pensight::mavlink
