#include "mavlink/vehicle_link.h"

#include <algorithm>
#include <limits>
#include <utility>

namespace pensight::mavlink {
namespace {

constexpr uint16_t kRcNeutralUs = 1500;
constexpr int kRcSpanUs = 400;
constexpr uint16_t kRcIgnore = std::numeric_limits<uint16_t>::max();

// True when a periodic message is due. The next one is then a period after this one's slot, so a
// late poll does not shift the cadence, or a period from now after a gap longer than a period.
bool due(std::optional<int64_t>& next_ns, int64_t period_ns, int64_t now_ns) {
  if (next_ns && now_ns < *next_ns) return false;
  next_ns = next_ns && now_ns - *next_ns < period_ns ? *next_ns + period_ns : now_ns + period_ns;
  return true;
}

int64_t boot_ns(uint32_t time_boot_ms) {
  return int64_t{time_boot_ms} * 1'000'000;
}

uint16_t rc_pulse(int value, int full_scale) {
  return static_cast<uint16_t>(kRcNeutralUs + value * kRcSpanUs / full_scale);
}

}  // namespace

VehicleLink::VehicleLink(LinkConfig config)
    : config_(std::move(config)),
      socket_(parse_endpoint(config_.endpoint)),
      attitude_clock_(config_.boot_clock),
      pressure_clock_(config_.boot_clock) {
  check_params<WaterDepthParams>(config_.water_depth, water_depth_params(), "water depth");
  const bool gcs = config_.role == LinkRole::kGroundStation;
  sysid_ = config_.sysid != 0 ? config_.sysid : (gcs ? 255 : 1);
  compid_ =
      config_.compid != 0 ? config_.compid : (gcs ? kCompIdMissionPlanner : kCompIdOnboardComputer);
  type_ = gcs ? kMavTypeGcs : kMavTypeOnboardController;
}

void VehicleLink::poll(int64_t now_ns) {
  received_.clear();
  socket_.receive(received_);
  for (const Frame& f : parser_.feed(received_)) handle(f, now_ns);
  if (due(next_heartbeat_ns_, config_.heartbeat_period_ns, now_ns)) {
    send(Heartbeat{
        .type = type_, .autopilot = kMavAutopilotInvalid, .system_status = kMavStateActive});
  }
  if (due(next_command_ns_, config_.control_period_ns, now_ns)) send_command(now_ns);
}

void VehicleLink::set_manual_control(int x, int y, int z, int r, int64_t stamped_ns,
                                     uint16_t buttons) {
  const auto axis = [](int v, int lo) { return static_cast<int16_t>(std::clamp(v, lo, 1000)); };
  command_ =
      Command{axis(x, -1000), axis(y, -1000), axis(z, 0), axis(r, -1000), buttons, stamped_ns};
}

bool VehicleLink::arm(bool armed) {
  return send(CommandLong{.param = {armed ? 1.0f : 0.0f},
                          .command = kCmdComponentArmDisarm,
                          .target_system = config_.target_system,
                          .target_component = config_.target_component});
}

bool VehicleLink::set_mode(SubMode mode) {
  return send(SetMode{.custom_mode = static_cast<uint32_t>(mode),
                      .target_system = config_.target_system,
                      .base_mode = kModeFlagCustomModeEnabled});
}

bool VehicleLink::request_message_rate(uint32_t msgid, double rate_hz) {
  return send(CommandLong{.param = {static_cast<float>(msgid), static_cast<float>(1e6 / rate_hz)},
                          .command = kCmdSetMessageInterval,
                          .target_system = config_.target_system,
                          .target_component = config_.target_component});
}

template <class Sample>
void VehicleLink::queue(std::vector<Sample>& samples, const Sample& s) {
  if (samples.size() >= kMaxQueuedSamples) {
    samples.erase(samples.begin());
    ++counters_.samples_dropped;
  }
  samples.push_back(s);
}

std::vector<AttitudeSample> VehicleLink::take_attitude_samples() {
  return std::exchange(attitudes_, {});
}

std::vector<PressureSample> VehicleLink::take_pressure_samples() {
  return std::exchange(pressures_, {});
}

LinkCounters VehicleLink::counters() const {
  LinkCounters c = counters_;
  c.send_errors = socket_.errors();
  c.parse = parser_.counters();
  return c;
}

template <class M>
bool VehicleLink::send(const M& message) {
  const bool sent = socket_.send(encode_frame(make_frame(message, seq_++, sysid_, compid_)));
  counters_.frames_sent += sent ? 1 : 0;
  return sent;
}

void VehicleLink::send_command(int64_t now_ns) {
  const bool fresh = command_ && now_ns - command_->stamped_ns < config_.command_timeout_ns &&
                     command_->stamped_ns - now_ns < config_.command_timeout_ns;
  const Command c = fresh ? *command_ : Command{};
  counters_.neutral_commands += fresh ? 0 : 1;
  if (config_.rc_override) {
    RcChannelsOverride rc;
    std::fill(rc.chan_raw.begin(), rc.chan_raw.begin() + 8, kRcIgnore);
    rc.chan_raw[2] = rc_pulse(c.z - 500, 500);
    rc.chan_raw[3] = rc_pulse(c.r, 1000);
    rc.chan_raw[4] = rc_pulse(c.x, 1000);
    rc.chan_raw[5] = rc_pulse(c.y, 1000);
    rc.target_system = config_.target_system;
    rc.target_component = config_.target_component;
    send(rc);
  } else {
    send(ManualControl{c.x, c.y, c.z, c.r, c.buttons, config_.target_system});
  }
}

void VehicleLink::handle(const Frame& f, int64_t now_ns) {
  if (f.sysid != config_.target_system || f.compid != config_.target_component) {
    ++counters_.other_senders;
    return;
  }
  if (f.msgid == Heartbeat::kId) {
    const auto hb = unpack<Heartbeat>(f.payload);
    status_.heartbeat_ns = now_ns;
    status_.armed = (hb.base_mode & kModeFlagSafetyArmed) != 0;
    status_.custom_mode = hb.custom_mode;
    status_.system_status = hb.system_status;
  } else if (f.msgid == SysStatus::kId) {
    status_.sys_status_ns = now_ns;
    status_.sys_status = unpack<SysStatus>(f.payload);
  } else if (f.msgid == Attitude::kId) {
    status_.attitude_ns = now_ns;
    const Attitude& a = status_.attitude = unpack<Attitude>(f.payload);
    queue(attitudes_, AttitudeSample{attitude_clock_.to_host_ns(boot_ns(a.time_boot_ms), now_ns),
                                     a.roll_rad, a.pitch_rad, a.yaw_rad, boot_ns(a.time_boot_ms)});
  } else if (f.msgid == ScaledPressure::kId || f.msgid == ScaledPressure2::kId ||
             f.msgid == ScaledPressure3::kId) {
    const int i = f.msgid == ScaledPressure::kId ? 0 : f.msgid == ScaledPressure2::kId ? 1 : 2;
    const ScaledPressure p = unpack<ScaledPressure>(f.payload);  // one layout for the three
    record_barometer(status_, i, p, now_ns, config_.water_depth);
    if (status_.water_index == i) {
      queue(pressures_, PressureSample{pressure_clock_.to_host_ns(boot_ns(p.time_boot_ms), now_ns),
                                       depth_from_pressure_m(p.press_abs_hpa, config_.water_depth),
                                       boot_ns(p.time_boot_ms)});
    }
  }
}

}  // namespace pensight::mavlink
