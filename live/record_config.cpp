#include "live/record_config.h"

#include <algorithm>
#include <cctype>

#include "core/error.h"
#include "core/strict_yaml.h"
#include "drivers/nucleus_dvl.h"
#include "drivers/waterlinked.h"
#include "drivers/waterlinked_dvl.h"
#include "mavlink/endpoint.h"
#include "pipeline/dataset/calibration_yaml.h"

namespace pensight::live {
namespace fs = std::filesystem;

namespace {

// The keys whose values are text: key, default as written, help. Read and documented from here.
struct TextKey {
  std::string_view key;
  std::string_view default_text;
  std::string_view help;
};

constexpr TextKey kSceneKey{"scene", "required",
                            "the net: a scene.yaml (../shared/dataset-format.md), relative to "
                            "this file"};
constexpr TextKey kCameraKeys[] = {
    {"uri", "required",
     "where frames come from: v4l2:/dev/video0, gst:PIPELINE, rtsp://, tcp://, "
     "a video file or dataset:DIR (live/camera_uri.h)"},
    {"calibration", "required", "a cam0/sensor.yaml: intrinsics, size every frame must have, T_BS"},
};
constexpr TextKey kDvlKeys[] = {
    {"kind", "required",
     "waterlinked (A50 / A125, JSON over TCP or serial sentences) or nucleus "
     "(Nortek Nucleus 1000, binary)"},
    {"host", "the kind's",
     "the DVL's address: 192.168.194.95 (Water Linked fallback), "
     "192.168.2.201 (Nucleus)"},
    {"serial_device", "none",
     "a serial device (/dev/ttyUSB0): the DVL's serial line instead of TCP"},
    {"calibration", "required", "a dvl0/sensor.yaml: T_BS and the beam directions"},
    {"password", "nortek", "Nucleus with start: the command port's password (Nortek's default)"},
};
constexpr TextKey kBottomTrackKeys[] = {
    {"mode", "the Nucleus's", "SETBT MODE: FAST_ACQ, AUTO or CRAWLER (Nortek's names)"},
};
constexpr TextKey kMavlinkKeys[] = {
    {"endpoint", "udpin:0.0.0.0:14550",
     "udpin:ADDR:PORT (BlueOS sends to 14550), "
     "udpout:HOST:PORT or tcp:HOST:PORT (BlueOS 5777, SITL 5760)"},
};

const Param<RecordDvl> kDvlParams[] = {
    {"port", &RecordDvl::port, "", closed_range(0, 65535),
     "TCP port; 0: the kind's (16171 Water Linked; Nucleus 9002, with start 9000)"},
    {"start",
     &RecordDvl::start,
     "",
     {},
     "Nucleus: on every connection log in on the command port, stop, set its clock to the host's "
     "UTC and START; the records follow there. Off: it was started elsewhere (web interface)"},
    {"dark_mode",
     &RecordDvl::dark_mode,
     "",
     {},
     "Water Linked: set dark_mode_enabled on every connection, so the LED does not flash into "
     "the camera"},
};

// dvl.bottom_track: sent as SETBT (with the bottom-track data stream on) before every START.
const Param<drivers::NucleusBottomTrack> kBottomTrackParams[] = {
    {"velocity_range_mps", &drivers::NucleusBottomTrack::velocity_range_mps, "m/s",
     closed_range(0, 10), "SETBT VR: the largest velocity measured; 0: the Nucleus's own"},
    {"water_track",
     &drivers::NucleusBottomTrack::water_track,
     "",
     {},
     "SETBT WT: water-track pings between the bottom-track pings (pensight leaves them out)"},
};

const Param<RecordConfig> kSessionParams[] = {
    {"silence_s", &RecordConfig::silence_s, "s", closed_range(0.1, 600),
     "a source without a sample for this long is said while recording, and again when it "
     "resumes"},
};

const Param<RecordMavlink> kMavlinkParams[] = {
    {"attitude_rate_hz", &RecordMavlink::attitude_rate_hz, "Hz", closed_range(0.1, 100),
     "ATTITUDE rate asked of the vehicle (MAV_CMD_SET_MESSAGE_INTERVAL)"},
    {"pressure_rate_hz", &RecordMavlink::pressure_rate_hz, "Hz", closed_range(0.1, 100),
     "SCALED_PRESSURE 1-3 rate asked of the vehicle"},
};

std::string text_rows(std::span<const TextKey> keys, std::string_view prefix) {
  std::string rows;
  for (const TextKey& k : keys) {
    rows += "| `" + std::string(prefix) + std::string(k.key) + "` | " +
            std::string(k.default_text) + " |  | text | " + std::string(k.help) + " |\n";
  }
  return rows;
}

fs::path resolve(const fs::path& base_dir, const std::string& path) {
  const fs::path p(path);
  return p.is_absolute() ? p : base_dir / p;
}

// A calibration file named by `key`, read by `read`, its errors prefixed with the key.
template <class Read>
auto read_named_file(const YamlMap& map, const std::string& key, const fs::path& base_dir,
                     Read read) {
  const fs::path file = resolve(base_dir, map.string(key));
  try {
    return read(file);
  } catch (const Error& e) {
    map.fail(key, e.what());
  }
}

RecordDvl read_dvl(const YamlMap& m, const fs::path& base_dir) {
  RecordDvl d;
  const std::string kind = m.string("kind");
  if (kind == "waterlinked") {
    d.kind = DvlKind::kWaterLinked;
  } else if (kind == "nucleus") {
    d.kind = DvlKind::kNucleus;
  } else {
    m.fail("kind", "'" + kind + "' is not a DVL kind; use waterlinked or nucleus");
  }
  read_params(m, std::span<const Param<RecordDvl>>(kDvlParams), d);
  const bool wl = d.kind == DvlKind::kWaterLinked;
  d.host = m.string("host",
                    wl ? drivers::WaterLinkedDvlConfig{}.host : drivers::NucleusDvlConfig{}.host);
  if (wl && d.start)
    m.fail("start", "a Water Linked DVL measures once powered; start is for a nucleus");
  if (d.port == 0) {
    d.port = wl        ? drivers::kWaterLinkedTcpPort
             : d.start ? drivers::kNucleusCommandPort
                       : drivers::kNucleusDataPort;
  }
  d.nucleus_command.password = m.string("password", d.nucleus_command.password);
  if (const auto bt = m.optional_map("bottom_track")) {
    if (d.kind != DvlKind::kNucleus || !d.start) {
      m.fail("bottom_track",
             "SETBT goes over the Nucleus's command port: set kind: nucleus and "
             "start: true, or leave bottom_track out");
    }
    drivers::NucleusBottomTrack b;
    b.mode = bt->string("mode", "");
    std::transform(b.mode.begin(), b.mode.end(), b.mode.begin(),
                   [](unsigned char ch) { return static_cast<char>(std::toupper(ch)); });
    if (!b.mode.empty() && !drivers::is_nucleus_bottom_track_mode(b.mode)) {
      bt->fail("mode",
               "'" + b.mode + "' is not a bottom-track mode; use FAST_ACQ, AUTO or CRAWLER");
    }
    read_params(*bt, std::span<const Param<drivers::NucleusBottomTrack>>(kBottomTrackParams), b);
    bt->check_unknown_keys();
    d.nucleus_command.bottom_track = b;
  }
  d.serial_device = m.string("serial_device", "");
  d.calibration = read_named_file(m, "calibration", base_dir, read_dvl_yaml);
  if (const auto s = m.optional_map("serial")) read_params(*s, serial_port_params(), d.serial);
  if (const auto t = m.optional_map("tcp")) read_params(*t, tcp_client_params(), d.tcp);
  if (const auto c = m.optional_map("clock")) read_params(*c, device_clock_params(), d.clock);
  return d;
}

RecordMavlink read_mavlink(const YamlMap& m) {
  RecordMavlink l;
  l.endpoint = m.string("endpoint", l.endpoint);
  try {
    mavlink::parse_endpoint(l.endpoint);
  } catch (const Error& e) {
    m.fail("endpoint", e.what());
  }
  read_params(m, std::span<const Param<RecordMavlink>>(kMavlinkParams), l);
  if (const auto w = m.optional_map("water_depth")) {
    read_params(*w, mavlink::water_depth_params(), l.water_depth);
  }
  if (const auto c = m.optional_map("clock")) read_params(*c, device_clock_params(), l.clock);
  return l;
}

RecordConfig read_config(const YamlMap& root, const fs::path& base_dir) {
  RecordConfig c;
  c.scene = read_named_file(root, std::string(kSceneKey.key), base_dir, read_scene_yaml);
  const YamlMap cam = root.map("camera");
  try {
    c.camera.uri = parse_camera_uri(cam.string("uri"));
  } catch (const Error& e) {
    cam.fail("uri", e.what());
  }
  if (c.camera.uri.kind == CameraUriKind::kDataset) {
    c.camera.uri.target = resolve(base_dir, c.camera.uri.target).string();
  }
  c.camera.calibration = read_named_file(cam, "calibration", base_dir, read_camera_yaml);
  read_params(cam, camera_source_params(), c.camera.source);
  cam.check_unknown_keys();
  if (const auto dvl = root.optional_map("dvl")) {
    c.dvl = read_dvl(*dvl, base_dir);
    dvl->check_unknown_keys();
  }
  if (const auto link = root.optional_map("mavlink")) {
    c.mavlink = read_mavlink(*link);
    link->check_unknown_keys();
  }
  read_params(root, std::span<const Param<RecordConfig>>(kSessionParams), c);
  root.check_unknown_keys();
  return c;
}

}  // namespace

const char* to_string(DvlKind kind) {
  return kind == DvlKind::kWaterLinked ? "waterlinked" : "nucleus";
}

RecordConfig parse_record_config(const std::string& text, const std::string& file,
                                 const fs::path& base_dir) {
  RecordConfig c = read_config(YamlMap::parse(text, file), base_dir);
  c.file = file;
  return c;
}

RecordConfig read_record_config(const fs::path& file) {
  RecordConfig c = read_config(YamlMap::load_file(file), file.parent_path());
  c.file = file;
  return c;
}

std::string record_config_param_rows() {
  std::string rows = text_rows(std::span(&kSceneKey, 1), "");
  rows += param_table_rows(std::span<const Param<RecordConfig>>(kSessionParams), {}, "");
  rows += text_rows(kCameraKeys, "camera.");
  rows += param_table_rows(camera_source_params(), {}, "camera.");
  rows += text_rows(kDvlKeys, "dvl.");
  rows += param_table_rows(std::span<const Param<RecordDvl>>(kDvlParams), {}, "dvl.");
  rows += text_rows(kBottomTrackKeys, "dvl.bottom_track.");
  rows += param_table_rows(std::span<const Param<drivers::NucleusBottomTrack>>(kBottomTrackParams),
                           {}, "dvl.bottom_track.");
  rows += param_table_rows(serial_port_params(), {}, "dvl.serial.");
  rows += param_table_rows(tcp_client_params(), {}, "dvl.tcp.");
  rows += param_table_rows(device_clock_params(), {}, "dvl.clock.");
  rows += text_rows(kMavlinkKeys, "mavlink.");
  rows += param_table_rows(std::span<const Param<RecordMavlink>>(kMavlinkParams), {}, "mavlink.");
  rows += param_table_rows(mavlink::water_depth_params(), {}, "mavlink.water_depth.");
  rows += param_table_rows(device_clock_params(), {}, "mavlink.clock.");
  return rows;
}

}  // namespace pensight::live
