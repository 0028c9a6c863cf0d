#include "sim/sensors.h"

#include <cmath>
#include <random>

#include "core/units.h"
#include "pipeline/dataset/sensor_mounts.h"
#include "sim/trajectory.h"

namespace pensight::sim {
namespace {

std::mt19937_64 stream(const Scenario& s, uint64_t id) {
  return std::mt19937_64(s.seed * 0x9E3779B97F4A7C15ull + id);
}

// Sample times k / rate for k = 0, 1, ... up to the scenario's duration.
template <class F>
void for_each_sample(const Scenario& s, double rate_hz, F&& f) {
  for (int k = 0;; ++k) {
    const double t = k / rate_hz;
    if (t > s.duration_s + 1e-9) break;
    f(t, s.start_time_ns + seconds_to_ns(t));
  }
}

}  // namespace

DvlCalibration dvl_calibration(const DvlConfig& dvl) {
  return janus_dvl_calibration(
      dvl.rate_hz, forward_mount(dvl.position_B_m, dvl.pan_rad, dvl.tilt_rad), dvl.beam_angle_rad);
}

DvlSample measure_dvl(const DvlConfig& cfg, const NetGeometry& net, const BodyState& b,
                      int64_t timestamp_ns, std::mt19937_64& rng) {
  const DvlCalibration calib = dvl_calibration(cfg);
  std::normal_distribution<double> gauss(0, 1);
  std::uniform_real_distribution<double> uniform(0, 1);
  const Eigen::Isometry3d T_pen_dvl = b.T_pen_body * calib.T_body_dvl;
  DvlSample d;
  d.timestamp_ns = timestamp_ns;
  int returns = 0;
  for (size_t k = 0; k < 4; ++k) {
    const Eigen::Vector3d dir = T_pen_dvl.linear() * calib.beam_directions_S[k];
    const auto hit = net.intersect(T_pen_dvl.translation(), dir);
    const double noise = gauss(rng);
    if (hit && hit->t <= cfg.max_range_m && hit->point.z() > 0) {
      d.beam_range_m[k] = hit->t + cfg.range_noise_m * noise;
      ++returns;
    }
  }
  Eigen::Vector3d v =
      (1 + cfg.scale_error) * b.T_pen_body.linear().transpose() * b.velocity_pen_mps +
      cfg.bias_B_mps;
  for (int i = 0; i < 3; ++i) v[i] += cfg.velocity_noise_mps * gauss(rng);
  if (uniform(rng) < cfg.spike_probability) {
    v[static_cast<int>(rng() % 3)] += (uniform(rng) < 0.5 ? -1 : 1) * cfg.spike_mps;
  }
  const bool dropout = uniform(rng) < cfg.dropout_probability;
  d.valid = returns >= 3 && !dropout;
  d.velocity_B_mps = d.valid ? v : Eigen::Vector3d::Constant(kNaN);
  if (dropout) d.beam_range_m.fill(kNaN);
  return d;
}

std::vector<DvlSample> simulate_dvl(const Scenario& s, const NetGeometry& net) {
  auto rng = stream(s, 1);
  std::vector<DvlSample> out;
  for_each_sample(s, s.dvl.rate_hz, [&](double t, int64_t ns) {
    DvlSample d = measure_dvl(s.dvl, net, body_state(s, t), ns, rng);
    for (const DvlSpike& spike : s.dvl.spikes)
      if (d.valid && t >= spike.t_s - 1e-9 && t < spike.t_s + spike.duration_s - 1e-9)
        d.velocity_B_mps += spike.velocity_B_mps;
    out.push_back(d);
  });
  return out;
}

PressureSample measure_pressure(const PressureConfig& cfg, const BodyState& body,
                                int64_t timestamp_ns, std::mt19937_64& rng) {
  std::normal_distribution<double> gauss(0, cfg.noise_m);
  return {timestamp_ns, body.T_pen_body.translation().z() + cfg.bias_m + gauss(rng)};
}

AttitudeSample measure_attitude(const AttitudeConfig& cfg, const BodyState& body,
                                int64_t timestamp_ns, std::mt19937_64& rng) {
  std::normal_distribution<double> gauss(0, cfg.noise_rad);
  const double roll = body.roll_rad + gauss(rng), pitch = body.pitch_rad + gauss(rng);
  return {timestamp_ns, roll, pitch, wrap_angle(body.yaw_rad + gauss(rng))};
}

std::vector<PressureSample> simulate_pressure(const Scenario& s) {
  auto rng = stream(s, 2);
  std::vector<PressureSample> out;
  for_each_sample(s, s.pressure.rate_hz, [&](double t, int64_t ns) {
    out.push_back(measure_pressure(s.pressure, body_state(s, t), ns, rng));
  });
  return out;
}

std::vector<AttitudeSample> simulate_attitude(const Scenario& s) {
  auto rng = stream(s, 3);
  std::vector<AttitudeSample> out;
  for_each_sample(s, s.attitude.rate_hz, [&](double t, int64_t ns) {
    out.push_back(measure_attitude(s.attitude, body_state(s, t), ns, rng));
  });
  return out;
}

}  // namespace pensight::sim
