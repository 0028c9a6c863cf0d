#include "live/device_standins.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <thread>

#include "core/error.h"
#include "core/tcp_server.h"
#include "core/timing.h"
#include "mavlink/endpoint.h"
#include "mavlink/messages.h"
#include "mavlink/water_depth.h"

namespace pensight::live {
namespace {

enum class Event { kFrame, kDvl, kPressure, kAttitude, kHeartbeat };

struct Scheduled {
  int64_t offset_ns;
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
  if (colon == std::string::npos) throw Error("camera uri '" + uri.text + "' has no port");
  return {rest.substr(0, colon), std::stoi(rest.substr(colon + 1))};
}

std::string format_double(double v) {
  char text[32];
  std::snprintf(text, sizeof text, "%.9g", v);
  return text;
}

// A Water Linked velocity report (json_v3.1) of one dataset sample, on the DVL's clock.
std::string velocity_report(const DvlSample& s, const DvlCalibration& calib, int64_t validity_us,
                            int64_t transmission_us) {
  const Eigen::Matrix3d R_S_B = calib.T_body_dvl.linear().transpose();
  const bool valid = s.valid && s.velocity_B_mps.allFinite();
  const Eigen::Vector3d v_S =
      valid ? Eigen::Vector3d(R_S_B * s.velocity_B_mps) : Eigen::Vector3d::Zero();
  std::string j = "{\"time\":100.0,\"vx\":" + format_double(v_S.x()) +
                  ",\"vy\":" + format_double(v_S.y()) + ",\"vz\":" + format_double(v_S.z()) +
                  ",\"fom\":0.002,\"altitude\":1.0,\"transducers\":[";
  for (size_t b = 0; b < 4; ++b) {
    const double r = s.beam_range_m[b];
    const bool beam = std::isfinite(r) && r >= 0;
    j += (b ? "," : "") + std::string("{\"id\":") + std::to_string(b) +
         ",\"velocity\":0.0,\"distance\":" + (beam ? format_double(r) : "-1.0") +
         ",\"rssi\":-30.0,\"nsd\":-95.0,\"beam_valid\":" + (beam ? "true" : "false") + "}";
  }
  j += "],\"velocity_valid\":" + std::string(valid ? "true" : "false") +
       ",\"status\":0,\"format\":\"json_v3.1\",\"type\":\"velocity\",\"time_of_validity\":" +
       std::to_string(validity_us) +
       ",\"time_of_transmission\":" + std::to_string(transmission_us) + "}\n";
  return j;
}

// The command a client's JSON line names ({"command":"NAME",...}), or empty.
std::string command_of(const std::string& line) {
  const std::string key = "\"command\":\"";
  const size_t at = line.find(key);
  if (at == std::string::npos) return "";
  const size_t start = at + key.size();
  const size_t end = line.find('"', start);
  return end == std::string::npos ? "" : line.substr(start, end - start);
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
      for (size_t n = camera->accept_new(); n > 0; --n)
        camera->send_to(camera->clients() - n, y4m_header);
      camera->take_lines();
    }
    if (dvl) {
      dvl->accept_new();
      for (const auto& [client, line] : dvl->take_lines()) {
        const std::string command = command_of(line);
        if (command.empty() || client >= dvl->clients()) continue;
        ++counters.commands;
        dvl->send_to(client, "{\"response_to\":\"" + command +
                                 "\",\"success\":true,\"error_message\":\"\",\"result\":null,"
                                 "\"format\":\"json_v3.1\",\"type\":\"response\"}\n");
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
    return static_cast<uint32_t>((offset_ns + static_cast<int64_t>(params.boot_offset_s * 1e9)) /
                                 1'000'000);
  }

  void send(const Scheduled& e, int64_t play_start_ns) {
    switch (e.event) {
      case Event::kFrame: {
        if (!camera) return;
        const double at_s = static_cast<double>(e.offset_ns) / 1e9;
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
        // The ping's own time (the report leaves dvl_delay_s later, at the event's time).
        const DvlSample& sample = dataset.dvl0->samples[e.index];
        const int64_t validity_ns = play_start_ns + (sample.timestamp_ns - t0) +
                                    static_cast<int64_t>(params.dvl_clock_offset_s * 1e9);
        const int64_t transmission_ns =
            validity_ns + static_cast<int64_t>(params.dvl_delay_s * 1e9);
        dvl->broadcast(velocity_report(sample, dataset.dvl0->calibration, validity_ns / 1000,
                                       transmission_ns / 1000));
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
    if (config.dvl->kind != DvlKind::kWaterLinked || !config.dvl->serial_device.empty()) {
      throw Error(
          "sim-devices stands in for a Water Linked DVL on TCP; set dvl.kind: waterlinked "
          "without dvl.serial_device");
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
  std::vector<Scheduled> events;
  int64_t& t0 = m.t0;
  t0 = d.frames.front().timestamp_ns;
  if (m.dvl) t0 = std::min(t0, d.dvl0->samples.empty() ? t0 : d.dvl0->samples.front().timestamp_ns);
  const bool vehicle = m.link || m.link_server;
  if (vehicle && d.pressure0 && !d.pressure0->empty())
    t0 = std::min(t0, d.pressure0->front().timestamp_ns);
  if (vehicle && d.imu0 && !d.imu0->empty()) t0 = std::min(t0, d.imu0->front().timestamp_ns);
  for (size_t i = 0; i < d.frames.size(); ++i)
    events.push_back({d.frames[i].timestamp_ns - t0, Event::kFrame, i});
  if (m.dvl) {
    for (size_t i = 0; i < d.dvl0->samples.size(); ++i) {
      events.push_back(
          {d.dvl0->samples[i].timestamp_ns - t0 + static_cast<int64_t>(m.params.dvl_delay_s * 1e9),
           Event::kDvl, i});
    }
  }
  if (vehicle) {
    if (d.pressure0) {
      for (size_t i = 0; i < d.pressure0->size(); ++i)
        events.push_back({(*d.pressure0)[i].timestamp_ns - t0, Event::kPressure, i});
    }
    if (d.imu0) {
      for (size_t i = 0; i < d.imu0->size(); ++i)
        events.push_back({(*d.imu0)[i].timestamp_ns - t0, Event::kAttitude, i});
    }
  }
  int64_t end_ns = 0;
  for (const Scheduled& e : events) end_ns = std::max(end_ns, e.offset_ns);
  if (vehicle) {
    for (int64_t t = 0; t <= end_ns; t += 1'000'000'000)
      events.push_back({t, Event::kHeartbeat, 0});
  }
  std::stable_sort(events.begin(), events.end(), [](const Scheduled& a, const Scheduled& b) {
    return a.offset_ns < b.offset_ns;
  });

  const int64_t lead_in_end = steady_now_ns() + static_cast<int64_t>(m.params.lead_in_s * 1e9);
  while (!stop.load() && steady_now_ns() < lead_in_end) {
    m.service_clients();
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
  }
  const int64_t host_start_ns = host_now_ns();
  const int64_t steady_start_ns = steady_now_ns();
  m.host_start_ns.store(host_start_ns);
  const int64_t disconnect_ns = m.params.dvl_disconnect_at_s < 0
                                    ? -1
                                    : static_cast<int64_t>(m.params.dvl_disconnect_at_s * 1e9);
  bool disconnected = false;
  for (const Scheduled& e : events) {
    while (!stop.load() && steady_now_ns() - steady_start_ns < e.offset_ns) {
      m.service_clients();
      std::this_thread::sleep_for(std::chrono::microseconds(500));
    }
    if (stop.load()) return;
    if (!disconnected && disconnect_ns >= 0 && e.offset_ns >= disconnect_ns && m.dvl) {
      m.dvl->disconnect_all();
      disconnected = true;
    }
    m.send(e, host_start_ns);
  }
  const int64_t linger_end = steady_now_ns() + static_cast<int64_t>(linger_s * 1e9);
  while (!stop.load() && steady_now_ns() < linger_end) {
    m.service_clients();
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
  }
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
