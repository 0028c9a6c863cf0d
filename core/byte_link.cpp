#include "core/byte_link.h"

#include "core/serial_port.h"
#include "core/tcp_client.h"

namespace pensight {

std::unique_ptr<ByteLink> make_byte_link(const std::string& serial_device,
                                         const SerialPortParams& serial, const std::string& host,
                                         int port, const TcpClientParams& tcp) {
  if (!serial_device.empty()) return std::make_unique<SerialPort>(serial_device, serial);
  return std::make_unique<TcpClient>(host, port, tcp);
}

}  // namespace pensight
