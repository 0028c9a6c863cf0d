#pragma once
// Depth below the surface from a pressure sensor's absolute pressure (sensor_msgs/FluidPressure
// gives pascals), hydrostatically: depth = (p - p_surface) / (rho g).
namespace pensight {

inline constexpr double kStandardGravity_mps2 = 9.80665;

struct WaterColumn {
  double density_kg_m3 = 1025.0;        // sea water; fresh water is ~1000
  double surface_pressure_pa = 101325;  // the atmosphere at the surface
};

// Depth [m], positive below the surface. Precondition: density_kg_m3 > 0.
inline double depth_from_pressure_m(double pressure_pa, const WaterColumn& w) {
  return (pressure_pa - w.surface_pressure_pa) / (w.density_kg_m3 * kStandardGravity_mps2);
}

// The inverse: absolute pressure [Pa] at depth_m.
inline double pressure_from_depth_pa(double depth_m, const WaterColumn& w) {
  return depth_m * w.density_kg_m3 * kStandardGravity_mps2 + w.surface_pressure_pa;
}

}  // namespace pensight
