#pragma once
// A Water Linked DVL A50 / A125 on its TCP JSON port as a source of the pipeline's DvlSamples:
// the connection kept up (TcpClient), the configuration sent on every connection (dark mode, so
// the LED does not flash into the camera), each bottom-track velocity report stamped at its ping
// on the host's clock (system_clock, ns since the Unix epoch, the DVL's clock mapped by a
// DeviceClock) and rotated into the body. Water-track reports (velocity through the water, not
// over the net) are counted and left out. Faults are counted (counters()), never thrown.
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "core/dataset_types.h"
#include "core/device_clock.h"
#include "core/tcp_client.h"
#include "drivers/waterlinked.h"

namespace pensight::drivers {

struct WaterLinkedDvlConfig {
  std::string host = "192.168.194.95";  // the DVL's static fallback address
  int port = kWaterLinkedTcpPort;
  Eigen::Matrix3d R_B_S = Eigen::Matrix3d::Identity();  // dvl0/sensor.yaml's T_BS rotation
  WaterLinkedConfig set_config;  // the members that are set are sent on every connection
  TcpClientParams tcp;
  DeviceClockParams clock;
};

struct WaterLinkedDvlCounters {
  size_t samples = 0;              // returned
  size_t water_track_skipped = 0;  // velocity through the water: not a DvlSample
  size_t config_refused = 0;       // set_config answered with success false
};

class WaterLinkedDvl {
 public:
  // Throws pensight::Error naming the address or key when the configuration is unusable.
  explicit WaterLinkedDvl(WaterLinkedDvlConfig config);

  // The samples whose reports arrive within timeout_s (returns early once one has).
  std::vector<DvlSample> poll(double timeout_s);

  const WaterLinkedDvlCounters& counters() const { return counters_; }
  const WaterLinkedCounters& stream_counters() const { return stream_.counters(); }
  const TcpClientCounters& connection_counters() const { return tcp_.counters(); }
  // The latest fault in words: a malformed line, a refused configuration, a dropped connection.
  std::string last_error() const;

 private:
  WaterLinkedDvlConfig config_;
  TcpClient tcp_;
  WaterLinkedStream stream_{WaterLinkedStream::Protocol::kJson};
  DeviceClock clock_;
  WaterLinkedDvlCounters counters_;
  std::string config_error_;
};

}  // namespace pensight::drivers
