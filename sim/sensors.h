#pragma once
// The vehicle's other sensors along the scenario's trajectory: DVL (forward-looking by default,
// body velocity and four beam ranges to the net, with dropouts and spikes), pressure depth and
// attitude. Each draws its noise from its own stream of the scenario seed, so every sensor is
// reproducible on its own.
#include <random>
#include <vector>

#include "core/dataset_types.h"
#include "sim/net_geometry.h"
#include "sim/scenario.h"
#include "sim/trajectory.h"

namespace pensight::sim {

// Mounting and beam directions (Janus, beams at 45 + k * 90 degrees around the DVL's z axis).
DvlCalibration dvl_calibration(const DvlConfig& dvl);

// Samples along the scenario's trajectory, each sensor from its own stream of the seed.
std::vector<DvlSample> simulate_dvl(const Scenario& s, const NetGeometry& net);
std::vector<PressureSample> simulate_pressure(const Scenario& s);
std::vector<AttitudeSample> simulate_attitude(const Scenario& s);

// One measurement at a given body state (closed loops, and the samplers above); each draws its
// noise from `rng`.
DvlSample measure_dvl(const DvlConfig& cfg, const NetGeometry& net, const BodyState& body,
                      int64_t timestamp_ns, std::mt19937_64& rng);
PressureSample measure_pressure(const PressureConfig& cfg, const BodyState& body,
                                int64_t timestamp_ns, std::mt19937_64& rng);
AttitudeSample measure_attitude(const AttitudeConfig& cfg, const BodyState& body,
                                int64_t timestamp_ns, std::mt19937_64& rng);

}  // namespace pensight::sim
