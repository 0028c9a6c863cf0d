#include "mavlink/water_depth.h"

#include <cmath>

#include "core/units.h"

namespace pensight::mavlink {
namespace {

constexpr double kGravity_mps2 = 9.80665;
constexpr double kPaPerHpa = 100.0;

const Param<WaterDepthParams> kWaterDepthParams[] = {
    {"pressure_source", &WaterDepthParams::pressure_source, "", closed_range(0, 3),
     "barometer of the water: 1-3 SCALED_PRESSURE, 2, 3; 0: the one reading the highest "
     "(averaged)"},
    {"water_density_kgpm3", &WaterDepthParams::water_density_kgpm3, "kg/m^3",
     closed_range(900, 1100), "water density: sea water 1025, fresh water 997"},
    {"surface_pressure_hpa", &WaterDepthParams::surface_pressure_hpa, "hPa",
     closed_range(800, 1100), "air pressure at the water's surface"},
    {"max_age_s", &WaterDepthParams::max_age_s, "s", kPositive,
     "a barometer not heard for longer is not used"},
    {"smoothing_s", &WaterDepthParams::smoothing_s, "s", kPositive,
     "automatic choice: each barometer's pressure averaged over about this long"},
    {"switch_margin_hpa", &WaterDepthParams::switch_margin_hpa, "hPa", kNonNegative,
     "automatic choice: another barometer takes over when its average is this much higher"},
};

}  // namespace

std::span<const Param<WaterDepthParams>> water_depth_params() {
  return kWaterDepthParams;
}

int water_pressure_index(const VehicleStatus& status, const WaterDepthParams& params,
                         int64_t now_ns) {
  check_params<WaterDepthParams>(params, kWaterDepthParams, "water depth");
  const auto fresh = [&](int i) {
    const int64_t heard = status.pressure_ns[static_cast<size_t>(i)];
    return heard >= 0 && now_ns - heard <= seconds_to_ns(params.max_age_s) &&
           status.pressure[static_cast<size_t>(i)].press_abs_hpa > 0;
  };
  if (params.pressure_source > 0) {
    return fresh(params.pressure_source - 1) ? params.pressure_source - 1 : -1;
  }
  if (status.first_pressure_ns < 0 ||
      now_ns - status.first_pressure_ns < seconds_to_ns(params.max_age_s)) {
    return -1;
  }
  int best = -1;
  for (int i = 0; i < 3; ++i) {
    if (fresh(i) && (best < 0 || status.pressure_average_hpa[static_cast<size_t>(i)] >
                                     status.pressure_average_hpa[static_cast<size_t>(best)])) {
      best = i;
    }
  }
  const auto average = [&](int i) { return status.pressure_average_hpa[static_cast<size_t>(i)]; };
  const int current = status.water_index;
  if (best >= 0 && current >= 0 && current < 3 && fresh(current) &&
      average(best) - average(current) <= params.switch_margin_hpa) {
    return current;
  }
  return best;
}

void record_barometer(VehicleStatus& status, int index, const ScaledPressure& reading,
                      int64_t now_ns, const WaterDepthParams& params) {
  const auto i = static_cast<size_t>(index);
  const int64_t previous_ns = status.pressure_ns[i];
  double& average = status.pressure_average_hpa[i];
  if (previous_ns < 0 || now_ns - previous_ns > seconds_to_ns(params.max_age_s)) {
    average = reading.press_abs_hpa;  // first, or after a silence: start again
  } else {
    const double step = 1 - std::exp(-seconds_between(previous_ns, now_ns) / params.smoothing_s);
    average += step * (reading.press_abs_hpa - average);
  }
  status.pressure_ns[i] = now_ns;
  if (status.first_pressure_ns < 0) status.first_pressure_ns = now_ns;
  status.pressure[i] = reading;
  status.water_index = water_pressure_index(status, params, now_ns);
}

double depth_from_pressure_m(double press_abs_hpa, const WaterDepthParams& params) {
  check_params<WaterDepthParams>(params, kWaterDepthParams, "water depth");
  return (press_abs_hpa - params.surface_pressure_hpa) * kPaPerHpa /
         (params.water_density_kgpm3 * kGravity_mps2);
}

double pressure_from_depth_hpa(double depth_m, const WaterDepthParams& params) {
  check_params<WaterDepthParams>(params, kWaterDepthParams, "water depth");
  return params.surface_pressure_hpa +
         depth_m * params.water_density_kgpm3 * kGravity_mps2 / kPaPerHpa;
}

}  // namespace pensight::mavlink
