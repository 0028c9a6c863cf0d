#include "drivers/nucleus_dvl.h"

#include "core/timing.h"

#include <string>
#include <utility>

namespace pensight::drivers {

DvlSample to_dvl_sample(const NucleusTrack& track, const Eigen::Matrix3d& R_B_S,
                        int64_t timestamp_ns) {
  DvlSample s;
  s.timestamp_ns = timestamp_ns;
  s.device_ns = track.time.device_ns;
  const Eigen::Vector3d v_S(track.velocity_mps[0], track.velocity_mps[1], track.velocity_mps[2]);
  s.valid = track.bottom && track.valid() && v_S.allFinite();
  s.velocity_B_mps = s.valid ? Eigen::Vector3d(R_B_S * v_S) : Eigen::Vector3d::Zero();
  for (size_t i = 0; i < track.beam_distance_m.size(); ++i) {
    if (track.beam_distance_m[i] > 0) s.beam_range_m[i] = track.beam_distance_m[i];
  }
  return s;
}

NucleusDvl::NucleusDvl(NucleusDvlConfig config)
    : config_(std::move(config)),
      link_(make_byte_link(config_.serial_device, config_.serial, config_.host, config_.port,
                           config_.tcp)),
      session_(config_.command),
      clock_(config_.clock) {}

std::vector<DvlSample> NucleusDvl::poll(double timeout_s) {
  std::vector<DvlSample> samples;
  std::vector<uint8_t> bytes = link_->read(timeout_s);
  const int64_t arrival_ns = host_now_ns();
  const bool new_connection = link_->take_new_connection();
  if (new_connection) stream_.restart();
  if (config_.start) {
    const int64_t now_ns = steady_now_ns();
    const std::string send =
        new_connection ? session_.restart(config_.serial_device.empty(), now_ns) : "";
    NucleusCommandSession::Step step = session_.feed(bytes, now_ns);
    for (const std::string& command : {send, step.send})
      if (!command.empty()) link_->write(command);
    bytes = std::move(step.stream);
  }
  for (const NucleusPacket& p : stream_.feed(bytes)) {
    const std::optional<NucleusTrack> track = decode_nucleus_track(p);
    if (!track) {
      ++counters_.other_records;
    } else if (!track->bottom) {
      ++counters_.water_track_skipped;
    } else {
      samples.push_back(to_dvl_sample(*track, config_.R_B_S,
                                      clock_.to_host_ns(track->time.device_ns, arrival_ns)));
      ++counters_.samples;
    }
  }
  return samples;
}

}  // namespace pensight::drivers
