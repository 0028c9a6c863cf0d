#include "mavlink/water_depth.h"

#include "core/units.h"

namespace pensight::mavlink {
namespace {

constexpr double kGravity_mps2 = 9.80665;
constexpr double kPaPerHpa = 100.0;

const Param<WaterDepthParams> kWaterDepthParams[] = {
    {"pressure_source", &WaterDepthParams::pressure_source, "", closed_range(0, 3),
     "barometer of the water: 1-3 SCALED_PRESSURE, 2, 3; 0: the one reading the highest pressure"},
    {"water_density_kgpm3", &WaterDepthParams::water_density_kgpm3, "kg/m^3",
     closed_range(900, 1100), "water density: sea water 1025, fresh water 997"},
    {"surface_pressure_hpa", &WaterDepthParams::surface_pressure_hpa, "hPa",
     closed_range(800, 1100), "air pressure at the water's surface"},
    {"max_age_s", &WaterDepthParams::max_age_s, "s", kPositive,
     "a barometer not heard for longer is not used"},
    {"switch_margin_hpa", &WaterDepthParams::switch_margin_hpa, "hPa", kNonNegative,
     "automatic choice: another barometer takes over only when it reads this much more"},
};

}  // namespace

std::span<const Param<WaterDepthParams>> water_depth_params() {
  return kWaterDepthParams;
}

int water_pressure_index(const VehicleStatus& status, const WaterDepthParams& params,
                         int64_t now_ns, int current) {
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
    if (fresh(i) && (best < 0 || status.pressure[static_cast<size_t>(i)].press_abs_hpa >
                                     status.pressure[static_cast<size_t>(best)].press_abs_hpa)) {
      best = i;
    }
  }
  const auto hpa = [&](int i) { return status.pressure[static_cast<size_t>(i)].press_abs_hpa; };
  if (current >= 0 && current < 3 && fresh(current) &&
      hpa(best) - hpa(current) <= params.switch_margin_hpa) {
    return current;
  }
  return best;
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
