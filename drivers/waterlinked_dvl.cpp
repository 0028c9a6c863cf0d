#include "drivers/waterlinked_dvl.h"

#include "core/timing.h"

#include <utility>
#include <variant>

namespace pensight::drivers {
namespace {

bool any_set(const WaterLinkedConfig& c) {
  return c.speed_of_sound_mps || c.mounting_rotation_offset_deg || c.acoustic_enabled ||
         c.dark_mode_enabled || c.range_mode || c.periodic_cycling_enabled;
}

}  // namespace

WaterLinkedDvl::WaterLinkedDvl(WaterLinkedDvlConfig config)
    : config_(std::move(config)),
      link_(make_byte_link(config_.serial_device, config_.serial, config_.host, config_.port,
                           config_.tcp)),
      stream_(config_.serial_device.empty() ? WaterLinkedStream::Protocol::kJson
                                            : WaterLinkedStream::Protocol::kSerial),
      clock_(config_.clock) {}

std::vector<DvlSample> WaterLinkedDvl::poll(double timeout_s) {
  std::vector<DvlSample> samples;
  const std::vector<uint8_t> bytes = link_->read(timeout_s);
  const int64_t arrival_ns = host_now_ns();
  if (link_->take_new_connection()) {
    stream_.restart();
    if (any_set(config_.set_config)) {
      link_->write(config_.serial_device.empty()
                       ? waterlinked_json_set_config(config_.set_config)
                       : waterlinked_set_config_sentence(config_.set_config));
    }
  }
  for (const WaterLinkedReport& r : stream_.feed(bytes)) {
    if (const auto* v = std::get_if<WaterLinkedVelocity>(&r)) {
      if (v->water_track) {
        ++counters_.water_track_skipped;
        continue;
      }
      samples.push_back(
          to_dvl_sample(*v, config_.R_B_S, waterlinked_ping_host_ns(*v, arrival_ns, clock_)));
      ++counters_.samples;
    } else if (const auto* resp = std::get_if<WaterLinkedResponse>(&r)) {
      // The serial protocol's naks do not name the command: set_config is the only one sent.
      const bool nak =
          resp->response_to == "wrn" || resp->response_to == "wr?" || resp->response_to == "wr!";
      if ((resp->response_to == "set_config" && !resp->success) || nak) {
        ++counters_.config_refused;
        config_error_ =
            "the DVL refused set_config: " + (nak ? resp->response_to : resp->error_message);
      }
    }
  }
  return samples;
}

std::string WaterLinkedDvl::last_error() const {
  if (!config_error_.empty()) return config_error_;
  if (!stream_.last_error().empty()) return "a malformed report: " + stream_.last_error();
  return link_->last_error();
}

}  // namespace pensight::drivers
