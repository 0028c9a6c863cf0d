#pragma once
// A Water Linked DVL A50 / A125 on its TCP JSON port, or on its serial line, as a source of the
// pipeline's DvlSamples: the connection kept up (TcpClient, SerialPort), the configuration sent on
// every connection (dark mode, so
// the LED does not flash into the camera), each bottom-track velocity report stamped at its ping
// on the host's clock (system_clock, ns since the Unix epoch, the DVL's clock mapped by a
// DeviceClock) and rotated into the body. Water-track reports (velocity through the water, not
// over the net) are counted and left out. On the serial line the beams come as separate `wru`
// sentences and are not attached: its samples have no beam ranges. Faults are counted
// (counters()), never thrown.
#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "core/byte_link.h"
#include "core/dataset_types.h"
#include "core/device_clock.h"
#include "core/serial_port.h"
#include "core/tcp_client.h"
#include "drivers/waterlinked.h"

namespace pensight::drivers {

struct WaterLinkedDvlConfig {
  std::string host = "192.168.194.95";  // the DVL's static fallback address
  int port = kWaterLinkedTcpPort;
  std::string serial_device;  // e.g. /dev/ttyUSB0: the serial protocol there instead of TCP
  SerialPortParams serial;
  Eigen::Matrix3d R_B_S = Eigen::Matrix3d::Identity();  // dvl0/sensor.yaml's T_BS rotation
  WaterLinkedConfig set_config;  // the members that are set are sent on every connection
  TcpClientParams tcp;
  DeviceClockParams clock;
};

struct WaterLinkedDvlCounters {
  size_t samples = 0;              // returned
  size_t water_track_skipped = 0;  // velocity through the water: not a DvlSample
  size_t config_refused = 0;       // set_config answered with success false (serial: a nak)
};

class WaterLinkedDvl {
 public:
  // Throws pensight::Error naming the address or key when the configuration is unusable.
  explicit WaterLinkedDvl(WaterLinkedDvlConfig config);

  // The samples whose reports arrive within timeout_s (returns early once one has).
  std::vector<DvlSample> poll(double timeout_s);

  const WaterLinkedDvlCounters& counters() const { return counters_; }
  const WaterLinkedCounters& stream_counters() const { return stream_.counters(); }
  const ByteLinkCounters& connection_counters() const { return link_->counters(); }
  // The latest fault in words: a malformed line, a refused configuration, a dropped connection.
  std::string last_error() const;

 private:
  WaterLinkedDvlConfig config_;
  std::unique_ptr<ByteLink> link_;
  WaterLinkedStream stream_;
  DeviceClock clock_;
  WaterLinkedDvlCounters counters_;
  std::string config_error_;
};

}  // namespace pensight::drivers
