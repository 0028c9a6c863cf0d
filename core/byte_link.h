#pragma once
// A device's byte stream that keeps itself connected (TcpClient, SerialPort), as the live sources
// read it: bytes within a timeout, writes that fail rather than block, and a flag per new
// connection so the caller re-sends its set-up commands. Faults are counted, never thrown.
#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

namespace pensight {

struct ByteLinkCounters {
  size_t connects = 0;          // connections made (a serial line: opened)
  size_t connect_failures = 0;  // refused, unreachable, timed out; no such device
  size_t drops = 0;             // closed by the peer, a hang-up, a read or write error
  size_t idle_timeouts = 0;     // closed by us after a silence
  size_t bytes_received = 0;
};

class ByteLink {
 public:
  virtual ~ByteLink() = default;
  // The bytes that arrive within timeout_s (returns at the first ones), connecting first when
  // due; empty when none came.
  virtual std::vector<uint8_t> read(double timeout_s) = 0;
  // Sends all of `bytes`; false when not connected or the send failed (then dropped, counted).
  virtual bool write(std::string_view bytes) = 0;
  // True once after each new connection.
  virtual bool take_new_connection() = 0;
  virtual const ByteLinkCounters& counters() const = 0;
  // The latest fault in words ("" before one).
  virtual const std::string& last_error() const = 0;
};

struct SerialPortParams;
struct TcpClientParams;

// A device's link as its configuration names it: its serial line (SerialPort) where
// serial_device is set, else TCP to host:port (TcpClient). Throws as their constructors do.
std::unique_ptr<ByteLink> make_byte_link(const std::string& serial_device,
                                         const SerialPortParams& serial, const std::string& host,
                                         int port, const TcpClientParams& tcp);

}  // namespace pensight
