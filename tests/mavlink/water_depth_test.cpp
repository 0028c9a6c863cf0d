// The vehicle's depth from ArduSub's barometers: the water sensor chosen by its reading (a BlueROV2
// sends its enclosure's air pressure beside the Bar30's, on a board-dependent message) or by
// configuration, stale and empty barometers left out, and the pressure-to-depth conversion.
#include "mavlink/water_depth.h"

#include <gtest/gtest.h>

#include <random>
#include <string>

#include "core/error.h"
#include "mavlink/vehicle_link.h"

namespace pensight::mavlink {
namespace {

constexpr int64_t kS = 1'000'000'000;

VehicleStatus barometers(float p0, float p1, float p2, int64_t heard_ns) {
  VehicleStatus s;
  s.pressure[0].press_abs_hpa = p0;
  s.pressure[1].press_abs_hpa = p1;
  s.pressure[2].press_abs_hpa = p2;
  s.pressure_average_hpa = {p0, p1, p2};
  s.pressure_ns = {heard_ns, heard_ns, heard_ns};
  s.first_pressure_ns = 0;
  return s;
}

TEST(WaterDepth, TheBarometerOfTheWaterIsTheOneReadingMost) {
  const WaterDepthParams p;
  // The enclosure's air on SCALED_PRESSURE, the Bar30 on SCALED_PRESSURE2, no third (SITL sends 0).
  VehicleStatus s = barometers(1003.5f, 1113.25f, 0.0f, 10 * kS);
  EXPECT_EQ(water_pressure_index(s, p, 11 * kS), 1);
  // The same with the boards' roles swapped.
  s = barometers(1113.25f, 1003.5f, 0.0f, 10 * kS);
  EXPECT_EQ(water_pressure_index(s, p, 11 * kS), 0);
  // Not heard for longer than max_age_s: not used.
  s.pressure_ns[0] = 8 * kS - 1;
  EXPECT_EQ(water_pressure_index(s, p, 10 * kS), 1);
  EXPECT_EQ(water_pressure_index(VehicleStatus{}, p, 10 * kS), -1);
  // Automatic only once barometers have been heard for max_age_s: the air's may come first.
  s.first_pressure_ns = 9 * kS;
  EXPECT_EQ(water_pressure_index(s, p, 10 * kS), -1);
  // Configured: that one, even when it reads less, and none when it is not heard.
  WaterDepthParams fixed;
  fixed.pressure_source = 2;
  EXPECT_EQ(water_pressure_index(barometers(1113.25f, 1003.5f, 0, kS), fixed, kS), 1);
  fixed.pressure_source = 3;
  EXPECT_EQ(water_pressure_index(barometers(1113.25f, 1003.5f, 0, kS), fixed, kS), -1);
}

// Two barometers near one pressure: the chosen one is kept until another's average is more than
// the margin above its own, or it falls silent.
TEST(WaterDepth, TheChosenBarometerIsKeptUntilAnotherIsClearlyHigher) {
  const WaterDepthParams p;
  const double m = p.switch_margin_hpa;
  VehicleStatus s = barometers(1051.3f, 1051.3f, 0.0f, 10 * kS);
  s.pressure_average_hpa[1] = 1051.3 + m - 1;
  EXPECT_EQ(water_pressure_index(s, p, 11 * kS), 1);  // no choice yet: the highest
  s.water_index = 0;
  EXPECT_EQ(water_pressure_index(s, p, 11 * kS), 0);  // within the margin above: kept
  s.pressure_average_hpa[1] = 1051.3 + m + 1;         // beyond it: taken over
  EXPECT_EQ(water_pressure_index(s, p, 11 * kS), 1);
  s.water_index = 1;
  s.pressure_average_hpa[1] = 1051.3 - m + 1;
  EXPECT_EQ(water_pressure_index(s, p, 11 * kS), 1);  // kept though it reads less now
  s.pressure_ns[1] = 8 * kS - 1;                      // silent: the other
  EXPECT_EQ(water_pressure_index(s, p, 10 * kS), 0);
}

// ArduSub SITL's barometers as recorded: both read the water, the second 18 hPa lower on average
// with +-20 hPa of noise, at 10 Hz. Its single readings are often the highest; its average never
// is, so the first stays the water's throughout. Then the vehicle dives with only the second
// (the Bar30 of a board whose first is the enclosure's air): the second takes over.
TEST(WaterDepth, ANoisyBarometerDoesNotTakeTheChoiceFromItsNoise) {
  const WaterDepthParams p;
  VehicleStatus s;
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> noise(-20, 20);
  int highest_readings = 0, changes = 0, chosen = -1;
  for (int k = 0; k < 600; ++k) {
    const int64_t t = k * kS / 10;
    ScaledPressure first, second;
    first.press_abs_hpa = 1051.3f;
    second.press_abs_hpa = static_cast<float>(1033.6 + noise(rng));
    record_barometer(s, 0, first, t, p);
    record_barometer(s, 1, second, t, p);
    highest_readings += second.press_abs_hpa > first.press_abs_hpa;
    if (s.water_index >= 0 && s.water_index != chosen) {
      changes += chosen >= 0;
      chosen = s.water_index;
    }
  }
  EXPECT_EQ(chosen, 0);
  EXPECT_EQ(changes, 0);
  EXPECT_GT(highest_readings, 20);  // the highest single reading would have flipped (~6 %)
  for (int k = 600; k < 700; ++k) {
    ScaledPressure air, water;
    air.press_abs_hpa = 1051.3f;
    water.press_abs_hpa = static_cast<float>(1033.6 + 2.0 * (k - 600));  // 0.2 m/s down
    record_barometer(s, 0, air, k * kS / 10, p);
    record_barometer(s, 1, water, k * kS / 10, p);
  }
  EXPECT_EQ(s.water_index, 1);
}

TEST(WaterDepth, DepthIsThePressureAboveTheSurfacesOverRhoG) {
  WaterDepthParams p;
  EXPECT_NEAR(depth_from_pressure_m(1013.25 + 100.52, p), 1.0, 1e-3);  // 1025 kg/m^3 x g x 1 m
  EXPECT_DOUBLE_EQ(depth_from_pressure_m(1013.25, p), 0.0);
  p.water_density_kgpm3 = 997;
  EXPECT_NEAR(depth_from_pressure_m(1013.25 + 97.77, p), 1.0, 1e-3);
  p.surface_pressure_hpa = 990;
  EXPECT_NEAR(depth_from_pressure_m(990 + 97.77, p), 1.0, 1e-3);
  EXPECT_THROW(
      VehicleLink({.endpoint = "udpin:127.0.0.1:0", .water_depth = {.pressure_source = 4}}), Error);
  p.water_density_kgpm3 = 0;
  try {
    depth_from_pressure_m(1100, p);
    FAIL() << "accepted";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("water_density_kgpm3"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace pensight::mavlink
