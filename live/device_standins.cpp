#include "live/device_standins.h"

#include <algorithm>
#include <charconv>
#include <chrono>
#include <cmath>
#include <thread>

#include "core/error.h"
#include "core/tcp_server.h"
#include "core/timing.h"
#include "core/units.h"
#include "drivers/nucleus_stream.h"
#include "drivers/waterlinked.h"
#include "mavlink/endpoint.h"
#include "mavlink/messages.h"
#include "mavlink/water_depth.h"

namespace pensight::live {
namespace {

enum class Event { kFrame, kDvl, kPressure, kAttitude, kHeartbeat };

struct Scheduled {
  int64_t offset_ns;  // from the first sample (its dataset time while the schedule is built)
  Event event;
  size_t index;
};

// HOST and PORT of "tcp://HOST:PORT[/...]", or throws naming the URI.
std::pair<std::string, int> tcp_address(const CameraUri& uri) {
  const std::string prefix = "tcp://";
  if (uri.kind != CameraUriKind::kNetwork || uri.target.rfind(prefix, 0) != 0) {
    throw Error("sim-devices serves the camera as tcp://HOST:PORT; set camera.uri to one (it is '" +
                uri.text + "')");
  }
  const std::string rest = uri.target.substr(
      prefix.size(), uri.target.find_first_of("/?", prefix.size()) - prefix.size());
  const size_t colon = rest.rfind(':');
  int port = -1;
  const char* end = rest.data() + rest.size();
  if (colon == std::string::npos ||
      std::from_chars(rest.data() + colon + 1, end, port).ptr != end || port < 0 || port > 65535) {
    throw Error("camera uri '" + uri.text + "': no port 0-65535 after the host (tcp://HOST:PORT)");
  }
  return {rest.substr(0, colon), port};
}

// A dataset sample's velocity back in the DVL's frame (meaningless for an invalid sample).
Eigen::Vector3d velocity_S(const DvlSample& s, const DvlCalibration& calib) {
  return calib.T_body_dvl.linear().transpose() * s.velocity_B_mps;
}

// The Water Linked report of one dataset sample: its velocity back in the DVL's frame, its beams'
// distances, the ping's time of validity and the report's transmission on the DVL's clock.
drivers::WaterLinkedVelocity velocity_report(const DvlSample& s, const DvlCalibration& calib,
                                             int64_t validity_us, int64_t transmission_us) {
  drivers::WaterLinkedVelocity v;
  v.valid = s.valid && s.velocity_B_mps.allFinite();
  if (v.valid) {
    const Eigen::Vector3d v_S = velocity_S(s, calib);
    v.velocity_mps = {v_S.x(), v_S.y(), v_S.z()};
  }
  v.fom_mps = 0.002;
  v.altitude_m = 1.0;
  v.since_last_report_ms = 100.0;
  for (size_t b = 0; b < s.beam_range_m.size(); ++b) {
    drivers::WaterLinkedBeam beam;
    beam.id = static_cast<int>(b);
    beam.distance_m = s.beam_range_m[b];
    beam.rssi_dbm = -30;
    beam.nsd_dbm = -95;
    beam.valid = std::isfinite(beam.distance_m) && beam.distance_m >= 0;
    v.beams.push_back(beam);
  }
  v.time_of_validity_us = validity_us;
  v.time_of_transmission_us = transmission_us;
  return v;
}

// The Nucleus's bottom-track record of one dataset sample: its velocity back in the DVL's frame,
// the first three beams' distances (0 where a beam has none), the ping's time on the DVL's clock.
std::vector<uint8_t> nucleus_record(const DvlSample& s, const DvlCalibration& calib,
                                    int64_t validity_ns) {
  drivers::NucleusTrack t;
  t.time = {validity_ns, true};
  const bool valid = s.valid && s.velocity_B_mps.allFinite();
  const Eigen::Vector3d v_S = velocity_S(s, calib);
  for (size_t i = 0; i < 3; ++i) {
    t.velocity_valid[i] = valid;
    t.velocity_mps[i] = v_S[static_cast<Eigen::Index>(i)];
    const double r = i < s.beam_range_m.size() ? s.beam_range_m[i] : 0.0;
    t.beam_distance_m[i] = std::isfinite(r) && r > 0 ? r : 0.0;
  }
  return drivers::encode_nucleus_packet(drivers::nucleus_track_packet(t));
}

}  // namespace

struct DeviceStandIns::Impl {
  Impl(const Dataset& d, RecordConfig c, StandInParams p)
      : dataset(d), config(std::move(c)), params(p) {}

  const Dataset& dataset;
  RecordConfig config;
  StandInParams params;
  StandInCounters counters;
  std::unique_ptr<TcpServer> camera;
  std::unique_ptr<TcpServer> dvl;
  std::unique_ptr<mavlink::Connection> link;  // UDP, or
  std::unique_ptr<TcpServer> link_server;     // TCP
  std::vector<uint8_t> link_received;
  uint8_t seq = 0;
  std::string y4m_header;
  std::atomic<int64_t> host_start_ns{0};
  int64_t t0 = 0;

  void service_clients() {
    if (camera) {
      for (const uint64_t client : camera->accept_new()) camera->send_to(client, y4m_header);
      camera->take_lines();
    }
    if (dvl) {
      dvl->accept_new();
      for (const auto& [client, line] : dvl->take_lines()) {
        if (config.dvl->kind == DvlKind::kNucleus) continue;  // its data port takes no commands
        const std::optional<std::string> command = drivers::waterlinked_json_command_name(line);
        if (!command) continue;
        ++counters.commands;
        dvl->send_to(client, drivers::waterlinked_json_response(*command, true));
      }
    }
    if (link) {
      link_received.clear();
      link->receive(link_received);
    }
    if (link_server) {
      link_server->accept_new();
      link_server->take_lines();
    }
  }

  // Answers clients until the steady clock reaches deadline_ns; false when `stop` came first.
  bool serve_until(int64_t deadline_ns, const std::atomic<bool>& stop) {
    while (!stop.load() && steady_now_ns() < deadline_ns) {
      service_clients();
      std::this_thread::sleep_for(std::chrono::microseconds(500));
    }
    return !stop.load();
  }

  template <class M>
  void send_mavlink(const M& m) {
    const std::vector<uint8_t> bytes =
        mavlink::encode_frame(mavlink::make_frame(m, seq++, 1, mavlink::kCompIdAutopilot));
    if (link) link->send(bytes);
    if (link_server) {
      link_server->broadcast(
          std::string_view(reinterpret_cast<const char*>(bytes.data()), bytes.size()));
    }
  }

  uint32_t boot_ms(int64_t offset_ns) const {
    return static_cast<uint32_t>((offset_ns + seconds_to_ns(params.boot_offset_s)) / 1'000'000);
  }

  void send(const Scheduled& e, int64_t play_start_ns) {
    switch (e.event) {
      case Event::kFrame: {
        if (!camera) return;
        const double at_s = ns_to_seconds(e.offset_ns);
        if (at_s >= params.camera_pause_at_s &&
            at_s < params.camera_pause_at_s + params.camera_pause_s)
          return;
        const ImageU8 image = dataset.load_frame(e.index);
        std::string frame = "FRAME\n";
        frame.append(image.pixels.begin(), image.pixels.end());
        camera->broadcast(frame);
        ++counters.frames;
        return;
      }
      case Event::kDvl: {
        if (!dvl) return;
        // The ping at the sample's time; the report stamped when it really leaves (dvl_delay_s
        // later as scheduled, or later still on a busy host), as the DVL stamps it: both on the
        // DVL's clock.
        const DvlSample& sample = dataset.dvl0->samples[e.index];
        const int64_t dvl_clock_ns = seconds_to_ns(params.dvl_clock_offset_s);
        const int64_t validity_ns = play_start_ns + (sample.timestamp_ns - t0) + dvl_clock_ns;
        if (config.dvl->kind == DvlKind::kNucleus) {
          const std::vector<uint8_t> record =
              nucleus_record(sample, dataset.dvl0->calibration, validity_ns);
          dvl->broadcast(
              std::string_view(reinterpret_cast<const char*>(record.data()), record.size()));
          ++counters.dvl_reports;
          return;
        }
        const int64_t transmission_ns = host_now_ns() + dvl_clock_ns;
        dvl->broadcast(drivers::waterlinked_json_velocity(velocity_report(
            sample, dataset.dvl0->calibration, validity_ns / 1000, transmission_ns / 1000)));
        ++counters.dvl_reports;
        return;
      }
      case Event::kPressure: {
        const mavlink::WaterDepthParams& w = config.mavlink->water_depth;
        mavlink::ScaledPressure air;  // the enclosure, a little below the surface's pressure
        air.time_boot_ms = boot_ms(e.offset_ns);
        air.press_abs_hpa = static_cast<float>(w.surface_pressure_hpa - 5);
        air.temperature_cdeg = 2500;
        send_mavlink(air);
        mavlink::ScaledPressure2 water;
        water.time_boot_ms = air.time_boot_ms;
        water.press_abs_hpa = static_cast<float>(
            mavlink::pressure_from_depth_hpa((*dataset.pressure0)[e.index].depth_m, w));
        water.temperature_cdeg = 1200;
        send_mavlink(water);
        ++counters.pressures;
        return;
      }
      case Event::kAttitude: {
        const AttitudeSample& a = (*dataset.imu0)[e.index];
        mavlink::Attitude m;
        m.time_boot_ms = boot_ms(e.offset_ns);
        m.roll_rad = static_cast<float>(a.roll_rad);
        m.pitch_rad = static_cast<float>(a.pitch_rad);
        m.yaw_rad = static_cast<float>(a.yaw_rad);
        send_mavlink(m);
        ++counters.attitudes;
        return;
      }
      case Event::kHeartbeat: {
        mavlink::Heartbeat h;
        h.custom_mode = 19;  // ArduSub MANUAL
        h.type = 12;         // MAV_TYPE_SUBMARINE
        h.autopilot = 3;     // MAV_AUTOPILOT_ARDUPILOTMEGA
        h.base_mode = mavlink::kModeFlagCustomModeEnabled;
        h.system_status = mavlink::kMavStateActive;
        send_mavlink(h);
        ++counters.heartbeats;
        return;
      }
    }
  }
};

DeviceStandIns::DeviceStandIns(const Dataset& dataset, const RecordConfig& config,
                               StandInParams params)
    : impl_(std::make_unique<Impl>(dataset, config, params)) {
  Impl& m = *impl_;
  const PinholeCamera& c = config.camera.calibration.camera;
  check_image_size(dataset.cam0.camera.width_px, dataset.cam0.camera.height_px, c,
                   "sim-devices: the dataset's cam0", "frame",
                   "record with the dataset's own cam0/sensor.yaml");
  const auto [camera_host, camera_port] = tcp_address(config.camera.uri);
  m.camera = std::make_unique<TcpServer>(camera_host, camera_port);
  m.y4m_header = "YUV4MPEG2 W" + std::to_string(c.width_px) + " H" + std::to_string(c.height_px) +
                 " F" +
                 std::to_string(std::max(1L, std::lround(config.camera.calibration.rate_hz))) +
                 ":1 Ip A1:1 Cmono\n";
  if (config.dvl && dataset.dvl0) {
    if (!config.dvl->serial_device.empty() ||
        (config.dvl->kind == DvlKind::kNucleus && config.dvl->start)) {
      throw Error(
          "sim-devices stands in for a Water Linked DVL on TCP or a Nucleus's TCP data port; "
          "leave out dvl.serial_device and, for a nucleus, dvl.start");
    }
    m.dvl = std::make_unique<TcpServer>(config.dvl->host, config.dvl->port);
  }
  if (config.mavlink) {
    const mavlink::Endpoint e = mavlink::parse_endpoint(config.mavlink->endpoint);
    const std::string port = std::to_string(e.port);
    switch (e.kind) {
      case mavlink::Endpoint::Kind::kUdpIn:
        m.link = std::make_unique<mavlink::Connection>(mavlink::parse_endpoint(
            "udpout:" + (e.host == "0.0.0.0" ? std::string("127.0.0.1") : e.host) + ":" + port));
        break;
      case mavlink::Endpoint::Kind::kUdpOut:
        m.link = std::make_unique<mavlink::Connection>(
            mavlink::parse_endpoint("udpin:" + e.host + ":" + port));
        break;
      case mavlink::Endpoint::Kind::kTcp:
        m.link_server = std::make_unique<TcpServer>(e.host, e.port);
        break;
    }
  }
}

DeviceStandIns::~DeviceStandIns() = default;

void DeviceStandIns::run(const std::atomic<bool>& stop, double linger_s) {
  Impl& m = *impl_;
  const Dataset& d = m.dataset;
  // Every sample at its dataset time, then as offsets from the first: a DVL report leaves
  // dvl_delay_s after its ping; heartbeats every second.
  std::vector<Scheduled> events;
  for (size_t i = 0; i < d.frames.size(); ++i) {
    events.push_back({d.frames[i].timestamp_ns, Event::kFrame, i});
  }
  if (m.dvl) {
    for (size_t i = 0; i < d.dvl0->samples.size(); ++i) {
      events.push_back({d.dvl0->samples[i].timestamp_ns, Event::kDvl, i});
    }
  }
  const bool vehicle = m.link || m.link_server;
  if (vehicle && d.pressure0) {
    for (size_t i = 0; i < d.pressure0->size(); ++i) {
      events.push_back({(*d.pressure0)[i].timestamp_ns, Event::kPressure, i});
    }
  }
  if (vehicle && d.imu0) {
    for (size_t i = 0; i < d.imu0->size(); ++i) {
      events.push_back({(*d.imu0)[i].timestamp_ns, Event::kAttitude, i});
    }
  }
  m.t0 = std::min_element(events.begin(), events.end(), [](const Scheduled& a, const Scheduled& b) {
           return a.offset_ns < b.offset_ns;
         })->offset_ns;
  int64_t end_ns = 0;
  for (Scheduled& e : events) {
    e.offset_ns -= m.t0;
    if (e.event == Event::kDvl) e.offset_ns += seconds_to_ns(m.params.dvl_delay_s);
    end_ns = std::max(end_ns, e.offset_ns);
  }
  if (vehicle) {
    for (int64_t t = 0; t <= end_ns; t += 1'000'000'000) {
      events.push_back({t, Event::kHeartbeat, 0});
    }
  }
  std::stable_sort(events.begin(), events.end(), [](const Scheduled& a, const Scheduled& b) {
    return a.offset_ns < b.offset_ns;
  });

  m.serve_until(steady_now_ns() + seconds_to_ns(m.params.lead_in_s), stop);
  const int64_t host_start_ns = host_now_ns();
  const int64_t steady_start_ns = steady_now_ns();
  m.host_start_ns.store(host_start_ns);
  // A fault at its time, once (never where its time is negative or there is no DVL).
  const auto due = [&](double at_s, bool& done, int64_t offset_ns) {
    if (done || at_s < 0 || !m.dvl || offset_ns < seconds_to_ns(at_s)) return false;
    return done = true;
  };
  bool disconnected = false, malformed = false;
  for (const Scheduled& e : events) {
    if (!m.serve_until(steady_start_ns + e.offset_ns, stop)) return;
    if (due(m.params.dvl_disconnect_at_s, disconnected, e.offset_ns)) m.dvl->disconnect_all();
    if (due(m.params.dvl_malformed_at_s, malformed, e.offset_ns)) {
      m.dvl->broadcast(R"({"type":"velocity","vx":"fast","vy":0,"vz":0,"velocity_valid":true})"
                       "\n");
    }
    m.send(e, host_start_ns);
  }
  m.serve_until(steady_now_ns() + seconds_to_ns(linger_s), stop);
}

DeviceStandIns::Ports DeviceStandIns::ports() const {
  Ports p;
  if (impl_->camera) p.camera = impl_->camera->port();
  if (impl_->dvl) p.dvl = impl_->dvl->port();
  if (impl_->link) p.mavlink = impl_->link->local_port();
  if (impl_->link_server) p.mavlink = impl_->link_server->port();
  return p;
}

int64_t DeviceStandIns::host_ns_of(int64_t dataset_ns) const {
  return impl_->host_start_ns.load() + (dataset_ns - impl_->t0);
}

StandInCounters DeviceStandIns::counters() const {
  return impl_->counters;
}

}  // namespace pensight::live
