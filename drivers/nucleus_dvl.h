#pragma once
// A Nortek Nucleus 1000 on its TCP data port (9002), its command port (9000), or its serial line,
// as a source of the pipeline's DvlSamples: the connection kept up (TcpClient, SerialPort), each
// bottom-track record stamped at its own time on the host's clock (system_clock, ns since the Unix
// epoch; the Nucleus's clock mapped by a DeviceClock, POSIX or not) and rotated into the body.
// Water-track records (velocity through the water) and the other records are counted and left out.
// The Nucleus streams once measuring: with `start`, this source logs in, sets the Nucleus's clock
// and starts it on every connection (NucleusCommandSession), the records following on that
// connection; without, it was started elsewhere (its web interface) and port 9002 carries them.
// Faults are counted (counters()), never thrown.
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
#include "drivers/nucleus_commands.h"
#include "drivers/nucleus_stream.h"

namespace pensight::drivers {

inline constexpr int kNucleusDataPort = 9002;

// The pipeline's DVL sample of a track record: the velocity rotated into the body by R_B_S,
// valid where the record is bottom track and all three velocity components are flagged valid,
// beam range r1-r3 each beam's distance where it is positive, device_ns the record's own time.
DvlSample to_dvl_sample(const NucleusTrack& track, const Eigen::Matrix3d& R_B_S,
                        int64_t timestamp_ns);

struct NucleusDvlConfig {
  std::string host = "192.168.2.201";
  int port = kNucleusDataPort;
  std::string serial_device;  // e.g. /dev/ttyUSB0: the same binary stream there instead of TCP
  SerialPortParams serial;
  Eigen::Matrix3d R_B_S = Eigen::Matrix3d::Identity();  // dvl0/sensor.yaml's T_BS rotation
  TcpClientParams tcp;
  DeviceClockParams clock;
  bool start = false;  // drive the command interface (port: kNucleusCommandPort over TCP)
  NucleusCommandParams command;
};

struct NucleusDvlCounters {
  size_t samples = 0;              // returned (valid or not: an invalid one says no lock)
  size_t water_track_skipped = 0;  // velocity through the water: not a DvlSample
  size_t other_records = 0;        // AHRS, altimeter, ...: passed over here
};

class NucleusDvl {
 public:
  // Throws pensight::Error naming the address or key when the configuration is unusable.
  explicit NucleusDvl(NucleusDvlConfig config);

  // The samples of the bottom-track records that arrive within timeout_s (returns early once
  // bytes came).
  std::vector<DvlSample> poll(double timeout_s);

  const NucleusDvlCounters& counters() const { return counters_; }
  const NucleusStreamCounters& stream_counters() const { return stream_.counters(); }
  const ByteLinkCounters& connection_counters() const { return link_->counters(); }
  const NucleusCommandCounters& command_counters() const { return session_.counters(); }
  // The latest fault of the connection, and of the commands with `start`.
  const std::string& last_error() const { return link_->last_error(); }
  const std::string& last_command_error() const { return session_.last_error(); }

 private:
  NucleusDvlConfig config_;
  std::unique_ptr<ByteLink> link_;
  NucleusCommandSession session_;
  NucleusStream stream_;
  DeviceClock clock_;
  NucleusDvlCounters counters_;
};

}  // namespace pensight::drivers
