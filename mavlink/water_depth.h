#pragma once
// The vehicle's depth from its barometers over MAVLink. ArduSub sends up to three
// (SCALED_PRESSURE, SCALED_PRESSURE2, SCALED_PRESSURE3) and which one is the water sensor (a
// BlueROV2's Bar30) differs by board; the others read the enclosure's air. Depth is the pressure
// above the surface's over rho g, with the water's density configured (ArduSub's own depth uses
// BARO_SPEC_GRAV, 1.0 by default: 2.5 % too deep in sea water).
#include <cstdint>
#include <span>

#include "core/params.h"
#include "mavlink/vehicle_status.h"

namespace pensight::mavlink {

struct WaterDepthParams {
  int pressure_source = 0;  // 1-3: SCALED_PRESSURE, 2, 3; 0: the one reading the highest pressure
  double water_density_kgpm3 = 1025.0;  // sea water; fresh water 997
  double surface_pressure_hpa = 1013.25;
  double max_age_s = 2.0;  // a barometer not heard for longer is not used (ArduSub sends 2 Hz)
  // Automatic choice: each barometer's pressure is averaged over about smoothing_s, and another
  // takes over from the chosen one only when its average is switch_margin_hpa above, so two
  // sensors near one pressure do not alternate with their noise (SITL's second barometer reads
  // the water with +-20 hPa of noise).
  double smoothing_s = 2.0;
  double switch_margin_hpa = 5.0;
};

// Key, unit, valid range and help of every WaterDepthParams member.
std::span<const Param<WaterDepthParams>> water_depth_params();

// Index (0-2) of the barometer that reads the water at now_ns, or -1 when it has not been heard
// within max_age_s. Automatic: of the barometers heard, the one with the highest average
// pressure above zero, since water adds ~100 hPa per metre while a sealed enclosure stays near the
// pressure it was closed at (at the surface the two agree within a few hPa, a few cm); none until
// barometers have been heard for max_age_s, so that every one the vehicle sends has spoken.
// status.water_index, the choice so far, is kept while it is heard and no other's average is more
// than switch_margin_hpa above its own.
int water_pressure_index(const VehicleStatus& status, const WaterDepthParams& params,
                         int64_t now_ns);

// A SCALED_PRESSURE(2, 3) message (index 0-2) heard at now_ns into `status`: the latest reading,
// its average, and the water's barometer chosen again (status.water_index).
void record_barometer(VehicleStatus& status, int index, const ScaledPressure& reading,
                      int64_t now_ns, const WaterDepthParams& params);

// Depth below the surface, m, for an absolute pressure in hPa. Throws pensight::Error naming the
// key when a parameter is out of its range.
double depth_from_pressure_m(double press_abs_hpa, const WaterDepthParams& params);
// The inverse: the absolute pressure in hPa at depth_m (a simulated vehicle's barometer).
double pressure_from_depth_hpa(double depth_m, const WaterDepthParams& params);

}  // namespace pensight::mavlink
