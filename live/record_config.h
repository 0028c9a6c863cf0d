#pragma once
// The YAML a live session reads (`pensight record`, and the vehicle program): which camera, DVL
// and autopilot link to use, their calibrations and the scene. One file, every key documented
// with its default in docs/vehicle.md (record_config_param_rows()). Paths inside it are relative
// to the file's own folder.
//
//   scene: scene.yaml                  # the net (a dataset's scene.yaml)
//   camera:
//     uri: "gst:udpsrc port=5600 ! ... ! appsink sync=false max-buffers=1 drop=true"
//     calibration: cam0.yaml           # a cam0/sensor.yaml
//     latency_s: 0.15
//   dvl:                               # absent: no DVL
//     kind: waterlinked                # waterlinked | nucleus
//     host: 192.168.194.95
//     calibration: dvl0.yaml           # a dvl0/sensor.yaml
//   mavlink:                           # absent: no depth, no attitude
//     endpoint: udpin:0.0.0.0:14550
#include <filesystem>
#include <optional>
#include <string>

#include "core/dataset_types.h"
#include "core/device_clock.h"
#include "core/serial_port.h"
#include "core/tcp_client.h"
#include "drivers/nucleus_commands.h"
#include "live/camera_source.h"
#include "live/camera_uri.h"
#include "mavlink/water_depth.h"

namespace pensight::live {

enum class DvlKind { kWaterLinked, kNucleus };
const char* to_string(DvlKind kind);  // "waterlinked" | "nucleus"

struct RecordCamera {
  CameraUri uri;
  CameraCalibration calibration;
  CameraSourceParams source;
};

struct RecordDvl {
  DvlKind kind = DvlKind::kWaterLinked;
  std::string host;           // default: the kind's factory address
  int port = 0;               // default: the kind's data port (16171, 9002)
  std::string serial_device;  // set: the serial line instead of TCP
  SerialPortParams serial;
  DvlCalibration calibration;
  bool dark_mode = true;  // Water Linked: the LED does not flash into the camera
  bool start = false;     // Nucleus: log in on the command port and start it on every connection
  drivers::NucleusCommandParams nucleus_command;
  TcpClientParams tcp;
  DeviceClockParams clock;
};

struct RecordMavlink {
  std::string endpoint = "udpin:0.0.0.0:14550";
  double attitude_rate_hz = 25;  // asked of the vehicle with MAV_CMD_SET_MESSAGE_INTERVAL
  double pressure_rate_hz = 10;
  mavlink::WaterDepthParams water_depth;
  DeviceClockParams clock;
};

struct RecordConfig {
  std::filesystem::path file;  // where it was read from
  SceneConfig scene;
  RecordCamera camera;
  std::optional<RecordDvl> dvl;
  std::optional<RecordMavlink> mavlink;
  double silence_s = 3;  // a source without a sample this long is said, and again when it resumes
};

// Reads `file`. Throws pensight::Error naming the file and key for anything missing, unknown,
// out of range or unreadable (a calibration file, a URI, an endpoint).
RecordConfig read_record_config(const std::filesystem::path& file);
// The same from text; paths resolve against base_dir (fuzz target, tests).
RecordConfig parse_record_config(const std::string& text, const std::string& file,
                                 const std::filesystem::path& base_dir);

// Markdown rows of every key, with defaults, for docs/vehicle.md and `pensight params`.
std::string record_config_param_rows();

}  // namespace pensight::live
