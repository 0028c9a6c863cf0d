#pragma once
// The vehicle's other sensors along the scenario's trajectory: DVL (forward-looking by default,
// body velocity and four beam ranges to the net, with dropouts and spikes), pressure depth and
// attitude. Each draws its noise from its own stream of the scenario seed, so every sensor is
// reproducible on its own.
#include <vector>

#include "pipeline/dataset/dataset_types.h"
#include "sim/net_geometry.h"
#include "sim/scenario.h"

namespace pensight::sim {

// Mounting and beam directions (Janus, beams at 45 + k * 90 degrees around the DVL's z axis).
DvlCalibration dvl_calibration(const DvlConfig& dvl);

std::vector<DvlSample> simulate_dvl(const Scenario& s, const NetGeometry& net);
std::vector<PressureSample> simulate_pressure(const Scenario& s);
std::vector<AttitudeSample> simulate_attitude(const Scenario& s);

}  // namespace pensight::sim
