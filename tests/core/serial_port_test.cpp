// SerialPort on a pseudo-terminal standing in for a DVL's UART: raw bytes both ways (no line-end
// translation, no echo), a device that goes away (hang-up, then no device), one that falls
// silent, and a path or a baud rate that cannot be used.
#include "core/serial_port.h"

#include <gtest/gtest.h>

#include <cstdlib>
#include <string>

#include "core/error.h"
#include "tests/support/fake_serial_device.h"

namespace pensight {
namespace {

using testing::FakeSerialDevice;

std::string as_text(const std::vector<uint8_t>& b) {
  return {b.begin(), b.end()};
}

TEST(SerialPort, RawBytesBothWaysThenTheDeviceGoesAway) {
  FakeSerialDevice dvl;
  SerialPort port(dvl.path(), {.reopen_delay_s = 0.05});
  EXPECT_TRUE(port.read(0.05).empty());
  ASSERT_TRUE(port.is_open()) << port.last_error();
  EXPECT_TRUE(port.take_new_connection());
  EXPECT_FALSE(port.take_new_connection());
  const std::string sentence = "wrx,112.83,0.007,0.017,0.006,0.000,0.93,y,0*d2\r\n";
  dvl.send(sentence);
  std::string got;
  for (int i = 0; i < 20 && got.size() < sentence.size(); ++i) got += as_text(port.read(0.5));
  EXPECT_EQ(got, sentence);  // the \r kept, nothing echoed or translated
  ASSERT_TRUE(port.write("wcv*00\n"));
  EXPECT_EQ(dvl.receive(7), "wcv*00\n");  // no \r added
  dvl.close();                            // the device goes away: a hang-up, then no such device
  for (int i = 0; i < 10; ++i) port.read(0.05);
  EXPECT_FALSE(port.is_open());
  EXPECT_EQ(port.counters().drops, 1u);
  EXPECT_GE(port.counters().connect_failures, 1u);
  EXPECT_EQ(port.counters().connects, 1u);
  EXPECT_EQ(port.counters().bytes_received, sentence.size());
  EXPECT_FALSE(port.write("wcv\n"));
}

TEST(SerialPort, ASilentDeviceIsReopened) {
  FakeSerialDevice dvl;
  SerialPort port(dvl.path(), {.reopen_delay_s = 0.0, .idle_timeout_s = 0.2});
  for (int i = 0; i < 6; ++i) port.read(0.1);
  EXPECT_GE(port.counters().idle_timeouts, 1u);
  EXPECT_GE(port.counters().connects, 2u);
  EXPECT_EQ(port.counters().drops, 0u);
}

TEST(SerialPort, NoDeviceIsCountedABadRateNamed) {
  SerialPort missing("/dev/pensight-no-such-dvl", {.reopen_delay_s = 0.02});
  for (int i = 0; i < 3; ++i) EXPECT_TRUE(missing.read(0.03).empty());
  EXPECT_GE(missing.counters().connect_failures, 2u);
  EXPECT_EQ(missing.last_error(), "open /dev/pensight-no-such-dvl: No such file or directory");
  SerialPort not_a_tty("/dev/null");
  not_a_tty.read(0.01);
  EXPECT_EQ(not_a_tty.counters().connect_failures, 1u);
  EXPECT_NE(not_a_tty.last_error().find("is not a serial line"), std::string::npos)
      << not_a_tty.last_error();
  try {
    SerialPort odd("/dev/ttyUSB0", {.baud = 100000});
    FAIL() << "accepted";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("key 'baud': 100000 is not a standard rate"),
              std::string::npos)
        << e.what();
  }
  EXPECT_THROW(SerialPort("/dev/ttyUSB0", {.idle_timeout_s = 0}), Error);
}

}  // namespace
}  // namespace pensight
