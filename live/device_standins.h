#pragma once
// Stand-ins for the devices of a live session (`pensight sim-devices`): a dataset's samples served
// on the addresses a record YAML names, in the devices' own protocols, at the dataset's time
// stamps in real time, so that `pensight record` (or the vehicle program) beside them runs as on
// the vehicle without the hardware:
// - the camera: a YUV4MPEG2 grey stream on a TCP server (camera.uri tcp://HOST:PORT), which
//   OpenCV's FFmpeg back-end reads losslessly;
// - a Water Linked DVL: its JSON velocity reports (format json_v3.1) on a TCP server at dvl.host
//   and dvl.port, each with the ping's time of validity and time of transmission on the DVL's own
//   clock, the beams' distances, and an answer to every command;
// - or a Nortek Nucleus's data port: a bottom-track record per sample (its velocity, the first
//   three beams' distances, the ping's time on the DVL's clock as a POSIX time);
// - ArduSub: HEARTBEAT at 1 Hz, ATTITUDE at imu0's rows, the water's pressure as SCALED_PRESSURE2
//   (and the enclosure's air as SCALED_PRESSURE) at pressure0's rows, each with time_boot_ms, to
//   the reverse of mavlink.endpoint (udpin -> sends to that port on 127.0.0.1; udpout -> listens
//   there; tcp -> a TCP server there).
#include <atomic>
#include <cstdint>
#include <memory>

#include "live/record_config.h"
#include "pipeline/dataset/dataset_reader.h"

namespace pensight::live {

struct StandInParams {
  double dvl_clock_offset_s = 0;  // the DVL's clock minus the host's
  double dvl_delay_s = 0;         // from the ping's time of validity to its report leaving
  double boot_offset_s = 60;      // the autopilot's time_boot_ms at the dataset's first sample
  double lead_in_s = 1.0;         // clients are served this long before the first sample
  // A camera stream that goes silent (the connection kept open) for pause_s from pause_at_s.
  double camera_pause_at_s = -1;
  double camera_pause_s = 0;
  double dvl_disconnect_at_s = -1;  // every DVL client's connection closed at this time
  double dvl_malformed_at_s = -1;   // a velocity report with a text for vx sent at this time
};

struct StandInCounters {
  uint64_t frames = 0, dvl_reports = 0, attitudes = 0, pressures = 0, heartbeats = 0;
  uint64_t commands = 0;  // DVL commands answered
};

class DeviceStandIns {
 public:
  // Opens the servers and sockets. Throws pensight::Error when the config's camera URI is not
  // tcp://HOST:PORT, its DVL is not a Water Linked on TCP or a Nucleus's TCP data port, an address
  // cannot be listened on, or the dataset's frames are not the config's calibration size.
  DeviceStandIns(const Dataset& dataset, const RecordConfig& config, StandInParams params = {});
  ~DeviceStandIns();
  DeviceStandIns(const DeviceStandIns&) = delete;
  DeviceStandIns& operator=(const DeviceStandIns&) = delete;

  // Serves connections for lead_in_s, then plays the dataset in real time; returns after its last
  // sample plus linger_s (clients read the tail), or at once when `stop` is set.
  void run(const std::atomic<bool>& stop, double linger_s = 0.5);
  StandInCounters counters() const;

  // The ports listened on (an address with port 0 gets an ephemeral one); 0 where none.
  struct Ports {
    int camera = 0, dvl = 0, mavlink = 0;
  };
  Ports ports() const;
  // The host time (system_clock ns) at which a dataset time stamp is played; valid once run() has
  // started playing.
  int64_t host_ns_of(int64_t dataset_ns) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace pensight::live
