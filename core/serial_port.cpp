#include "core/serial_port.h"

#include <fcntl.h>
#include <poll.h>
#include <termios.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <utility>

#include "core/error.h"
#include "core/internal/fd_io.h"
#include "core/timing.h"
#include "core/units.h"

namespace pensight {
namespace {

const Param<SerialPortParams> kSerialPortParams[] = {
    {"baud", &SerialPortParams::baud, "bit/s", closed_range(9600, 921600),
     "9600, 19200, 38400, 57600, 115200, 230400, 460800 or 921600"},
    {"reopen_delay_s", &SerialPortParams::reopen_delay_s, "s", kNonNegative,
     "between a failure or a loss of the device and the next open"},
    {"idle_timeout_s", &SerialPortParams::idle_timeout_s, "s", kPositive,
     "no byte for this long while open: the device stopped sending, reopen"},
};

struct Speed {
  int baud;
  speed_t constant;
};
constexpr Speed kSpeeds[] = {{9600, B9600},     {19200, B19200},   {38400, B38400},
                             {57600, B57600},   {115200, B115200}, {230400, B230400},
                             {460800, B460800}, {921600, B921600}};

}  // namespace

std::span<const Param<SerialPortParams>> serial_port_params() {
  return kSerialPortParams;
}

SerialPort::SerialPort(std::string path, SerialPortParams params)
    : path_(std::move(path)), params_(params) {
  check_params<SerialPortParams>(params_, kSerialPortParams, "serial port " + path_);
  const auto* s = std::find_if(std::begin(kSpeeds), std::end(kSpeeds),
                               [&](const Speed& sp) { return sp.baud == params_.baud; });
  if (s == std::end(kSpeeds)) {
    throw Error("serial port " + path_ + ": key 'baud': " + std::to_string(params_.baud) +
                " is not a standard rate; use 9600, 19200, 38400, 57600, 115200, 230400, 460800 "
                "or 921600");
  }
  speed_ = s->constant;
}

SerialPort::~SerialPort() {
  if (fd_ >= 0) ::close(fd_);
}

void SerialPort::drop(std::string why, bool idle) {
  if (fd_ >= 0) ::close(fd_);
  fd_ = -1;
  ++(idle ? counters_.idle_timeouts : counters_.drops);
  last_error_ = std::move(why);
  next_open_ns_ = steady_now_ns() + seconds_to_ns(params_.reopen_delay_s);
}

void SerialPort::try_open() {
  next_open_ns_ = steady_now_ns() + seconds_to_ns(params_.reopen_delay_s);
  const int fd = ::open(path_.c_str(), O_RDWR | O_NOCTTY | O_NONBLOCK | O_CLOEXEC);
  if (fd < 0) {
    ++counters_.connect_failures;
    last_error_ = "open " + path_ + ": " + std::strerror(errno);
    return;
  }
  termios t{};
  if (::tcgetattr(fd, &t) != 0) {
    const int err = errno;
    ::close(fd);
    ++counters_.connect_failures;
    last_error_ = path_ + " is not a serial line: " + std::strerror(err);
    return;
  }
  ::cfmakeraw(&t);
  t.c_cflag &= ~static_cast<tcflag_t>(CSTOPB | PARENB | CRTSCTS);
  t.c_cflag |= CLOCAL | CREAD | CS8;
  t.c_cc[VMIN] = 0;
  t.c_cc[VTIME] = 0;
  ::cfsetispeed(&t, speed_);
  ::cfsetospeed(&t, speed_);
  if (::tcsetattr(fd, TCSANOW, &t) != 0) {
    const int err = errno;
    ::close(fd);
    ++counters_.connect_failures;
    last_error_ = "configure " + path_ + ": " + std::strerror(err);
    return;
  }
  ::tcflush(fd, TCIFLUSH);  // bytes from before the open are not this session's
  fd_ = fd;
  ++counters_.connects;
  new_connection_ = true;
  last_byte_ns_ = steady_now_ns();
}

std::vector<uint8_t> SerialPort::read(double timeout_s) {
  std::vector<uint8_t> bytes;
  const int64_t deadline = steady_now_ns() + seconds_to_ns(timeout_s);
  for (;;) {
    const int64_t now = steady_now_ns();
    if (fd_ < 0) {
      if (now >= next_open_ns_) {
        try_open();
        if (fd_ >= 0) continue;
      }
      const int64_t until = std::min(deadline, next_open_ns_);
      if (until > steady_now_ns()) ::poll(nullptr, 0, poll_timeout_ms(until - steady_now_ns()));
      if (steady_now_ns() >= deadline) return bytes;
      continue;
    }
    const int64_t idle_at = last_byte_ns_ + seconds_to_ns(params_.idle_timeout_s);
    if (now >= idle_at) {
      drop("no byte from " + path_ + " for " + std::to_string(params_.idle_timeout_s) + " s", true);
      continue;
    }
    int err = 0;
    // A hang-up (the device gone) reads 0 bytes or fails with EIO.
    switch (detail::read_some(fd_, std::min(deadline, idle_at), bytes, &err)) {
      case detail::FdRead::kBytes:
        counters_.bytes_received += bytes.size();
        last_byte_ns_ = steady_now_ns();
        return bytes;
      case detail::FdRead::kClosed:
        drop(path_ + " hung up", false);
        break;
      case detail::FdRead::kFailed:
        drop(path_ + ": " + std::strerror(err), false);
        break;
      case detail::FdRead::kTimeout:
        break;
    }
    if (steady_now_ns() >= deadline) return bytes;
  }
}

bool SerialPort::write(std::string_view bytes) {
  if (fd_ < 0) return false;
  int err = 0;
  if (detail::write_all(fd_, bytes, false, 1000, &err)) return true;
  drop("write " + path_ + ": " + std::strerror(err), false);
  return false;
}

bool SerialPort::take_new_connection() {
  return std::exchange(new_connection_, false);
}

}  // namespace pensight
