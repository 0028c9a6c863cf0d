#pragma once
// A serial line (a DVL's UART, often behind a USB adapter: /dev/ttyUSB0) opened raw: 8N1, no flow
// control, no echo, no line editing, at a configured baud rate. It keeps itself open: a device
// that vanishes (an adapter unplugged), hangs up or fails is closed and reopened after
// reopen_delay_s, and a device silent for idle_timeout_s is reopened too; each is counted, never
// thrown after construction. No call blocks longer than its timeout. One thread uses it.
#include <cstddef>
#include <cstdint>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "core/byte_link.h"
#include "core/params.h"

namespace pensight {

struct SerialPortParams {
  int baud = 115200;            // 9600, 19200, 38400, 57600, 115200, 230400, 460800 or 921600
  double reopen_delay_s = 1.0;  // between a failure or a loss and the next open
  double idle_timeout_s = 3.0;  // no byte for this long while open: reopen
};

// Key, unit, valid range and help of every SerialPortParams member.
std::span<const Param<SerialPortParams>> serial_port_params();

class SerialPort final : public ByteLink {
 public:
  // Throws pensight::Error naming the key for a parameter out of range or a baud rate the line
  // cannot be set to. Opens lazily.
  explicit SerialPort(std::string path, SerialPortParams params = {});
  ~SerialPort();
  SerialPort(const SerialPort&) = delete;
  SerialPort& operator=(const SerialPort&) = delete;

  // The bytes that arrive within timeout_s (returns at the first ones), opening first if due;
  // empty when none came.
  std::vector<uint8_t> read(double timeout_s) override;
  // Writes all of `bytes`; false when the line is not open or the write failed (then dropped).
  bool write(std::string_view bytes) override;
  // True once after each open: the caller re-sends its set-up commands.
  bool take_new_connection() override;

  bool is_open() const { return fd_ >= 0; }
  const ByteLinkCounters& counters() const override { return counters_; }
  const std::string& last_error() const override { return last_error_; }
  const std::string& path() const { return path_; }

 private:
  void try_open();
  void drop(std::string why, bool idle);

  std::string path_;
  SerialPortParams params_;
  unsigned speed_ = 0;  // the termios speed constant of params_.baud
  int fd_ = -1;
  bool new_connection_ = false;
  int64_t next_open_ns_ = 0;  // steady clock
  int64_t last_byte_ns_ = 0;
  ByteLinkCounters counters_;
  std::string last_error_;
};

}  // namespace pensight
