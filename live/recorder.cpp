#include "live/recorder.h"

#include <limits>

#include "core/timing.h"
#include "core/units.h"
#include "drivers/nucleus_dvl.h"
#include "drivers/waterlinked_dvl.h"
#include "mavlink/messages.h"
#include "mavlink/vehicle_link.h"
#include "pipeline/dataset/dataset_writer.h"

namespace pensight::live {
namespace {

DatasetContents contents_of(const RecordConfig& c) {
  DatasetContents d;
  d.scene = c.scene;
  d.cam0 = c.camera.calibration;
  if (c.dvl) d.dvl0 = c.dvl->calibration;
  d.pressure0 = c.mavlink.has_value();
  d.imu0 = c.mavlink.has_value();
  d.groundtruth0 = false;
  d.device_times = true;
  return d;
}

std::string link_faults(const ByteLinkCounters& c) {
  return "connects " + std::to_string(c.connects) + ", connect failures " +
         std::to_string(c.connect_failures) + ", drops " + std::to_string(c.drops) +
         ", idle timeouts " + std::to_string(c.idle_timeouts);
}

// The link and mounting a DVL driver's config shares with every other (both drivers' configs
// have these members).
template <class DriverConfig>
DriverConfig driver_config(const RecordDvl& d) {
  DriverConfig c;
  c.host = d.host;
  c.port = d.port;
  c.serial_device = d.serial_device;
  c.serial = d.serial;
  c.R_B_S = d.calibration.T_body_dvl.linear();
  c.tcp = d.tcp;
  c.clock = d.clock;
  return c;
}

// One sensor log being written: its summary and its latest time stamp.
struct Log {
  SourceSummary summary;
  int64_t last_ns = std::numeric_limits<int64_t>::min();
};

// A sample into its log: time order kept (the writer refuses a stamp that does not increase; a
// live source's is counted instead), the latest clock offset remembered.
template <class Sample>
void write_sample(const Sample& s, Log& log, auto&& add) {
  SourceSummary& summary = log.summary;
  if (s.timestamp_ns <= log.last_ns) {
    ++summary.out_of_order;
    return;
  }
  log.last_ns = s.timestamp_ns;
  add(s);
  ++summary.samples;
  if constexpr (requires { s.device_ns; }) {
    if (s.device_ns) summary.clock_offset_ns = s.timestamp_ns - *s.device_ns;
  }
}

}  // namespace

struct Recorder::Sources {
  RecordConfig config;
  DatasetWriter writer;
  CameraSource camera;
  std::unique_ptr<drivers::WaterLinkedDvl> waterlinked;
  std::unique_ptr<drivers::NucleusDvl> nucleus;
  std::unique_ptr<mavlink::VehicleLink> link;
  bool rates_requested = false;
  Log cam{{"cam0"}}, dvl{{"dvl0"}}, pressure{{"pressure0"}}, imu{{"imu0"}};
  int64_t start_steady_ns = 0, end_steady_ns = 0;

  Sources(const RecordConfig& c, const std::filesystem::path& out)
      : config(c),
        writer(out, contents_of(c), DatasetWriteMode::kStreaming),
        camera(c.camera.uri, c.camera.calibration.camera, c.camera.source) {
    if (c.dvl && c.dvl->kind == DvlKind::kWaterLinked) {
      drivers::WaterLinkedDvlConfig w = driver_config<drivers::WaterLinkedDvlConfig>(*c.dvl);
      if (c.dvl->dark_mode) w.set_config.dark_mode_enabled = true;
      waterlinked = std::make_unique<drivers::WaterLinkedDvl>(w);
    } else if (c.dvl) {
      nucleus =
          std::make_unique<drivers::NucleusDvl>(driver_config<drivers::NucleusDvlConfig>(*c.dvl));
    }
    if (c.mavlink) {
      mavlink::LinkConfig l;
      l.endpoint = c.mavlink->endpoint;
      l.role = mavlink::LinkRole::kCompanionComputer;
      l.water_depth = c.mavlink->water_depth;
      l.boot_clock = c.mavlink->clock;
      link = std::make_unique<mavlink::VehicleLink>(l);
    }
  }

  void poll_camera(double wait_s) {
    if (std::optional<CameraFrame> f = camera.take(wait_s)) {
      write_sample(*f, cam, [&](const CameraFrame& frame) {
        writer.add_frame(frame.timestamp_ns, frame.image);
      });
    }
  }

  void poll_dvl() {
    std::vector<DvlSample> samples;
    if (waterlinked) samples = waterlinked->poll(0);
    if (nucleus) samples = nucleus->poll(0);
    for (const DvlSample& s : samples) {
      write_sample(s, dvl, [&](const DvlSample& x) { writer.add_dvl(x); });
    }
  }

  void poll_link() {
    if (!link) return;
    link->poll(host_now_ns());
    // ArduSub answers rate requests once it knows the link: after its first message.
    if (!rates_requested && link->status().heartbeat_ns >= 0) {
      rates_requested = true;
      link->request_message_rate(mavlink::Attitude::kId, config.mavlink->attitude_rate_hz);
      for (const uint32_t id : {mavlink::ScaledPressure::kId, mavlink::ScaledPressure2::kId,
                                mavlink::ScaledPressure3::kId}) {
        link->request_message_rate(id, config.mavlink->pressure_rate_hz);
      }
    }
    for (const AttitudeSample& s : link->take_attitude_samples()) {
      write_sample(s, imu, [&](const AttitudeSample& x) { writer.add_attitude(x); });
    }
    for (const PressureSample& s : link->take_pressure_samples()) {
      write_sample(s, pressure, [&](const PressureSample& x) { writer.add_pressure(x); });
    }
  }
};

Recorder::Recorder(const RecordConfig& config, const std::filesystem::path& out)
    : sources_(std::make_unique<Sources>(config, out)) {}

Recorder::~Recorder() = default;

void Recorder::run(double duration_s, const std::atomic<bool>& stop) {
  Sources& s = *sources_;
  s.start_steady_ns = steady_now_ns();
  const double end_ns = static_cast<double>(s.start_steady_ns) + duration_s * 1e9;
  while (!stop.load() && static_cast<double>(steady_now_ns()) < end_ns && !s.camera.finished()) {
    s.poll_camera(0.002);
    s.poll_dvl();
    s.poll_link();
  }
  s.end_steady_ns = steady_now_ns();
  s.writer.finish();
}

std::vector<SourceSummary> Recorder::summary() const {
  const Sources& s = *sources_;
  std::vector<SourceSummary> out;
  SourceSummary cam = s.cam.summary;
  const CameraCounters c = s.camera.counters();
  cam.faults = "dropped " + std::to_string(c.dropped) + ", wrong size " +
               std::to_string(c.wrong_size) + ", stalls " + std::to_string(c.stalls) +
               ", reconnects " + std::to_string(c.reconnects) + ", open failures " +
               std::to_string(c.open_failures);
  out.push_back(cam);
  if (s.waterlinked || s.nucleus) {
    SourceSummary d = s.dvl.summary;
    if (s.waterlinked) {
      const drivers::WaterLinkedCounters& w = s.waterlinked->stream_counters();
      d.faults = "malformed " + std::to_string(w.malformed) + ", checksum failures " +
                 std::to_string(w.checksum_failures) + ", water track skipped " +
                 std::to_string(s.waterlinked->counters().water_track_skipped) + ", " +
                 link_faults(s.waterlinked->connection_counters());
    } else {
      const drivers::NucleusStreamCounters& n = s.nucleus->stream_counters();
      d.faults = "checksum failures " + std::to_string(n.checksum_failures) + ", skipped bytes " +
                 std::to_string(n.skipped_bytes) + ", " +
                 link_faults(s.nucleus->connection_counters());
    }
    out.push_back(d);
  }
  if (s.link) {
    const mavlink::LinkCounters l = s.link->counters();
    const std::string faults = "bad crc " + std::to_string(l.parse.bad_crc) + ", dropped " +
                               std::to_string(l.samples_dropped) + ", link errors " +
                               std::to_string(l.send_errors);
    SourceSummary p = s.pressure.summary, i = s.imu.summary;
    p.faults = i.faults = faults;
    out.push_back(p);
    out.push_back(i);
  }
  return out;
}

std::string Recorder::summary_text() const {
  const double length_s = seconds_between(sources_->start_steady_ns, sources_->end_steady_ns);
  std::string text = "recorded " + format_param_value(length_s) + " s\n";
  for (const SourceSummary& s : summary()) {
    char rate[32];
    std::snprintf(rate, sizeof rate, "%.2f",
                  length_s > 0 ? static_cast<double>(s.samples) / length_s : 0.0);
    text += "  " + s.name + ": " + std::to_string(s.samples) + " samples (" + rate + " Hz)";
    if (s.out_of_order > 0) text += ", " + std::to_string(s.out_of_order) + " out of order";
    if (s.clock_offset_ns) {
      char offset[48];
      std::snprintf(offset, sizeof offset, ", host - device clock %.6f s",
                    ns_to_seconds(*s.clock_offset_ns));
      text += offset;
    }
    text += "; " + s.faults + "\n";
  }
  return text;
}

}  // namespace pensight::live
