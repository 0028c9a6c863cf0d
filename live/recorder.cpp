#include "live/recorder.h"

#include <cstdio>
#include <limits>
#include <map>

#include "core/log.h"
#include "core/timing.h"
#include "core/units.h"
#include "drivers/nucleus_dvl.h"
#include "drivers/waterlinked_dvl.h"
#include "mavlink/messages.h"
#include "mavlink/vehicle_link.h"
#include "pipeline/dataset/dataset_writer.h"

namespace pensight::live {
namespace {

// Faults are said at most this often per source, so a flapping link does not flood the log.
constexpr int64_t kFaultCheck_ns = 1'000'000'000;

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

void add_link_faults(std::vector<FaultCount>& faults, const ByteLinkCounters& c) {
  faults.insert(faults.end(), {{"connects", c.connects, true},
                               {"connect failures", c.connect_failures},
                               {"drops", c.drops},
                               {"idle timeouts", c.idle_timeouts}});
}

// "drops 1, malformed 0"
std::string faults_text(const std::vector<FaultCount>& faults) {
  std::string text;
  for (const FaultCount& f : faults) {
    text += (text.empty() ? "" : ", ") + f.name + " " + std::to_string(f.count);
  }
  return text;
}

std::string seconds_text(double s) {
  char text[32];
  std::snprintf(text, sizeof text, "%.1f s", s);
  return text;
}

// Whether a counter that grew from `before` is a fault to say.
bool is_fault(const FaultCount& f, uint64_t before) {
  return !f.first_is_expected || before > 0;
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

// One sensor log being written: its summary, its latest time stamp, and when its latest sample
// arrived (steady clock; the recording's start before the first).
struct Log {
  SourceSummary summary;
  int64_t last_ns = std::numeric_limits<int64_t>::min();
  int64_t arrived_steady_ns = 0;
  bool silent = false;  // said to be silent and not yet said to be back
  bool active = false;  // the session has this source
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
  const int64_t now_ns = steady_now_ns();
  if (log.silent) {
    log_info(summary.name + ": samples again after " +
             seconds_text(seconds_between(log.arrived_steady_ns, now_ns)));
    log.silent = false;
  }
  log.arrived_steady_ns = now_ns;
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
  std::map<std::string, std::vector<FaultCount>> said;  // per source, as last said
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
      drivers::NucleusDvlConfig n = driver_config<drivers::NucleusDvlConfig>(*c.dvl);
      n.start = c.dvl->start;
      n.command = c.dvl->nucleus_command;
      nucleus = std::make_unique<drivers::NucleusDvl>(n);
    }
    if (c.mavlink) {
      mavlink::LinkConfig l;
      l.endpoint = c.mavlink->endpoint;
      l.role = mavlink::LinkRole::kCompanionComputer;
      l.water_depth = c.mavlink->water_depth;
      l.boot_clock = c.mavlink->clock;
      link = std::make_unique<mavlink::VehicleLink>(l);
    }
    cam.active = true;
    dvl.active = waterlinked || nucleus;
    pressure.active = imu.active = link != nullptr;
  }

  std::vector<SourceSummary> summary() const {
    std::vector<SourceSummary> out;
    SourceSummary c = cam.summary;
    const CameraCounters k = camera.counters();
    c.faults = {{"dropped", k.dropped},
                {"wrong size", k.wrong_size},
                {"stalls", k.stalls},
                {"reconnects", k.reconnects},
                {"open failures", k.open_failures}};
    out.push_back(c);
    if (dvl.active) {
      SourceSummary d = dvl.summary;
      if (waterlinked) {
        const drivers::WaterLinkedCounters& w = waterlinked->stream_counters();
        d.faults = {{"malformed", w.malformed},
                    {"checksum failures", w.checksum_failures},
                    {"water track skipped", waterlinked->counters().water_track_skipped}};
        add_link_faults(d.faults, waterlinked->connection_counters());
      } else {
        const drivers::NucleusStreamCounters& n = nucleus->stream_counters();
        d.faults = {{"checksum failures", n.checksum_failures},
                    {"skipped bytes", n.skipped_bytes},
                    {"command failures", nucleus->command_counters().failures, false,
                     nucleus->last_command_error()}};
        add_link_faults(d.faults, nucleus->connection_counters());
      }
      out.push_back(d);
    }
    if (pressure.active) {
      const mavlink::LinkCounters l = link->counters();
      SourceSummary p = pressure.summary, i = imu.summary;
      p.faults = i.faults = {{"bad crc", l.parse.bad_crc},
                             {"dropped", l.samples_dropped},
                             {"link errors", l.send_errors}};
      out.push_back(p);
      out.push_back(i);
    }
    return out;
  }

  // Said while recording: each source's counters that grew since they were last said, and a
  // source silent for silence_s. pressure0 and imu0 share the link's counters: said once, as
  // "mavlink".
  void say_faults(int64_t now_ns) {
    for (const SourceSummary& s : summary()) {
      const std::string who = s.name == "pressure0" || s.name == "imu0" ? "mavlink" : s.name;
      std::vector<FaultCount>& before = said[who];
      std::string grew;
      for (size_t i = 0; i < s.faults.size(); ++i) {
        const uint64_t was = i < before.size() ? before[i].count : 0;
        if (s.faults[i].count > was && is_fault(s.faults[i], was)) {
          grew += (grew.empty() ? "" : ", ") + s.faults[i].name + " +" +
                  std::to_string(s.faults[i].count - was) + " (" +
                  std::to_string(s.faults[i].count) + ")" +
                  (s.faults[i].reason.empty() ? "" : ": " + s.faults[i].reason);
        }
      }
      if (!grew.empty()) log_warning(who + ": " + grew);
      before = s.faults;
    }
    const int64_t silence_ns = seconds_to_ns(config.silence_s);
    for (Log* log : {&cam, &dvl, &pressure, &imu}) {
      if (!log->active || log->silent || now_ns - log->arrived_steady_ns < silence_ns) continue;
      log->silent = true;
      log_warning(log->summary.name + ": no sample for " +
                  seconds_text(seconds_between(log->arrived_steady_ns, now_ns)) +
                  (log->summary.samples == 0 ? " since the recording started" : ""));
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
  for (Log* log : {&s.cam, &s.dvl, &s.pressure, &s.imu}) log->arrived_steady_ns = s.start_steady_ns;
  const double end_ns = static_cast<double>(s.start_steady_ns) + duration_s * 1e9;
  int64_t next_check_ns = s.start_steady_ns;
  while (!stop.load() && static_cast<double>(steady_now_ns()) < end_ns && !s.camera.finished()) {
    s.poll_camera(0.002);
    s.poll_dvl();
    s.poll_link();
    if (const int64_t now_ns = steady_now_ns(); now_ns >= next_check_ns) {
      s.say_faults(now_ns);
      next_check_ns = now_ns + kFaultCheck_ns;
    }
  }
  s.end_steady_ns = steady_now_ns();
  s.writer.finish();
}

std::vector<SourceSummary> Recorder::summary() const {
  return sources_->summary();
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
    text += "; " + faults_text(s.faults) + "\n";
  }
  return text;
}

}  // namespace pensight::live
