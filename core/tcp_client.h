#pragma once
// A TCP client to a device's data port (a Water Linked DVL's 16171, a Nortek Nucleus's 9002) that
// keeps itself connected: a refused or timed-out connect is retried after reconnect_delay_s, a
// closed connection or one silent for longer than idle_timeout_s (a device that stopped answering
// without closing) is closed and reconnected. Network failures are counted, never thrown; the
// caller sees bytes, or none. The connect does not block: a call that starts one returns within
// its own timeout, and a later call finishes it. One thread uses it.
#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "core/byte_link.h"
#include "core/params.h"

namespace pensight {

struct TcpClientParams {
  double connect_timeout_s = 2.0;  // a connect not done by then is a failure
  double reconnect_delay_s = 0.5;  // between a failure or a drop and the next connect
  double idle_timeout_s = 3.0;     // no byte for this long on a connection: reconnect
};

// The IPv4 address (host byte order) a host name or dotted quad resolves to, or nullopt with the
// resolver's reason in *why. Shared with MAVLink's endpoints.
std::optional<uint32_t> resolve_ipv4(const std::string& host, std::string* why);

// Key, unit, valid range and help of every TcpClientParams member.
std::span<const Param<TcpClientParams>> tcp_client_params();

class TcpClient final : public ByteLink {
 public:
  // Throws pensight::Error naming the address when `host` does not resolve to IPv4 or `port` is
  // outside 1..65535, and naming the key when a parameter is out of its range. Connects lazily.
  TcpClient(std::string host, int port, TcpClientParams params = {});
  ~TcpClient();
  TcpClient(const TcpClient&) = delete;
  TcpClient& operator=(const TcpClient&) = delete;

  // The bytes that arrive within timeout_s (returns at the first ones), connecting first if
  // needed; empty when none came.
  std::vector<uint8_t> read(double timeout_s) override;
  // Sends all of `bytes` on the current connection; false when there is none or it failed (then
  // it is dropped and counted).
  bool write(std::string_view bytes) override;
  // True once after each new connection: the caller re-sends its set-up commands.
  bool take_new_connection() override;

  bool connected() const { return fd_ >= 0 && !connecting_; }
  const ByteLinkCounters& counters() const override { return counters_; }
  const std::string& last_error() const override { return last_error_; }
  const std::string& address() const { return address_; }

 private:
  void start_connect();
  void finish_connect(int timeout_ms);
  void drop(std::string why, bool idle);
  void fail_connect(int err);

  std::string address_;  // host:port, for messages
  uint32_t ipv4_ = 0;
  uint16_t port_ = 0;
  TcpClientParams params_;
  int fd_ = -1;
  bool connecting_ = false;  // fd_ is a connect in progress
  int64_t connect_deadline_ns_ = 0;
  bool new_connection_ = false;
  int64_t next_connect_ns_ = 0;  // steady clock
  int64_t last_byte_ns_ = 0;
  ByteLinkCounters counters_;
  std::string last_error_;
};

}  // namespace pensight
