#pragma once
// A serial device for the tests: the device's end of a pseudo-terminal, whose other end (path())
// a SerialPort opens as it would /dev/ttyUSB0. Header-only, POSIX.
#include <fcntl.h>
#include <poll.h>
#include <stdlib.h>
#include <unistd.h>

#include <gtest/gtest.h>

#include <string>

namespace pensight::testing {

class FakeSerialDevice {
 public:
  FakeSerialDevice() {
    master_ = ::posix_openpt(O_RDWR | O_NOCTTY);
    EXPECT_GE(master_, 0);
    EXPECT_EQ(::grantpt(master_), 0);
    EXPECT_EQ(::unlockpt(master_), 0);
    path_ = ::ptsname(master_);
  }
  ~FakeSerialDevice() { close(); }
  FakeSerialDevice(const FakeSerialDevice&) = delete;
  FakeSerialDevice& operator=(const FakeSerialDevice&) = delete;
  void close() {
    if (master_ >= 0) ::close(master_);
    master_ = -1;
  }
  const std::string& path() const { return path_; }
  void send(const std::string& s) {
    ASSERT_EQ(::write(master_, s.data(), s.size()), static_cast<ssize_t>(s.size()));
  }
  std::string receive(size_t n) {
    std::string got;
    pollfd p{master_, POLLIN, 0};
    char buf[256];
    while (got.size() < n && ::poll(&p, 1, 2000) == 1) {
      const ssize_t k = ::read(master_, buf, sizeof buf);
      if (k <= 0) break;
      got.append(buf, static_cast<size_t>(k));
    }
    return got;
  }

 private:
  int master_ = -1;
  std::string path_;
};

}  // namespace pensight::testing
