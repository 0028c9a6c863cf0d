#include "core/tcp_client.h"

#include <arpa/inet.h>
#include <netdb.h>
#include <netinet/in.h>
#include <netinet/tcp.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <memory>
#include <utility>

#include "core/error.h"
#include "core/internal/fd_io.h"
#include "core/timing.h"
#include "core/units.h"

namespace pensight {
namespace {

const Param<TcpClientParams> kTcpClientParams[] = {
    {"connect_timeout_s", &TcpClientParams::connect_timeout_s, "s", kPositive,
     "a connect not done by then is a failure"},
    {"reconnect_delay_s", &TcpClientParams::reconnect_delay_s, "s", kNonNegative,
     "between a failure or a drop and the next connect"},
    {"idle_timeout_s", &TcpClientParams::idle_timeout_s, "s", kPositive,
     "no byte for this long on a connection: the device stopped answering, reconnect"},
};

}  // namespace

std::optional<uint32_t> resolve_ipv4(const std::string& host, std::string* why) {
  addrinfo hints{};
  hints.ai_family = AF_INET;
  addrinfo* found = nullptr;
  const int rc = ::getaddrinfo(host.c_str(), nullptr, &hints, &found);
  if (rc != 0 || found == nullptr) {
    *why = ::gai_strerror(rc);
    return std::nullopt;
  }
  const std::unique_ptr<addrinfo, decltype(&::freeaddrinfo)> owner(found, &::freeaddrinfo);
  return ntohl(reinterpret_cast<const sockaddr_in*>(found->ai_addr)->sin_addr.s_addr);
}

std::span<const Param<TcpClientParams>> tcp_client_params() {
  return kTcpClientParams;
}

TcpClient::TcpClient(std::string host, int port, TcpClientParams params)
    : address_(host + ":" + std::to_string(port)), params_(params) {
  check_params<TcpClientParams>(params_, kTcpClientParams, "TCP client " + address_);
  if (port < 1 || port > 65535) {
    throw Error("TCP client " + address_ + ": port " + std::to_string(port) +
                " is outside 1..65535");
  }
  std::string why;
  const std::optional<uint32_t> ipv4 = resolve_ipv4(host, &why);
  if (!ipv4) {
    throw Error("TCP client " + address_ + ": host '" + host +
                "' does not resolve to an IPv4 address (" + why +
                "); give the device's IP address");
  }
  ipv4_ = *ipv4;
  port_ = static_cast<uint16_t>(port);
}

TcpClient::~TcpClient() {
  if (fd_ >= 0) ::close(fd_);
}

void TcpClient::drop(std::string why, bool idle) {
  if (fd_ >= 0) ::close(fd_);
  fd_ = -1;
  connecting_ = false;
  ++(idle ? counters_.idle_timeouts : counters_.drops);
  last_error_ = std::move(why);
  next_connect_ns_ = steady_now_ns() + seconds_to_ns(params_.reconnect_delay_s);
}

void TcpClient::fail_connect(int err) {
  if (fd_ >= 0) ::close(fd_);
  fd_ = -1;
  connecting_ = false;
  ++counters_.connect_failures;
  last_error_ = "connect to " + address_ + ": " + std::strerror(err);
}

void TcpClient::start_connect() {
  const int64_t now = steady_now_ns();
  next_connect_ns_ = now + seconds_to_ns(params_.reconnect_delay_s);
  fd_ = ::socket(AF_INET, SOCK_STREAM | SOCK_NONBLOCK | SOCK_CLOEXEC, 0);
  if (fd_ < 0) {
    fail_connect(errno);
    return;
  }
  sockaddr_in a{};
  a.sin_family = AF_INET;
  a.sin_addr.s_addr = htonl(ipv4_);
  a.sin_port = htons(port_);
  connecting_ = true;
  connect_deadline_ns_ = now + seconds_to_ns(params_.connect_timeout_s);
  if (::connect(fd_, reinterpret_cast<const sockaddr*>(&a), sizeof a) == 0) {
    finish_connect(0);
  } else if (errno != EINPROGRESS) {
    fail_connect(errno);
  }
}

void TcpClient::finish_connect(int timeout_ms) {
  pollfd p{fd_, POLLOUT, 0};
  const int rc = ::poll(&p, 1, timeout_ms);
  if (rc < 0 && errno != EINTR) {
    fail_connect(errno);
    return;
  }
  if (rc <= 0) {
    if (steady_now_ns() >= connect_deadline_ns_) fail_connect(ETIMEDOUT);
    return;
  }
  int err = 0;
  socklen_t len = sizeof err;
  ::getsockopt(fd_, SOL_SOCKET, SO_ERROR, &err, &len);
  if (err != 0) {
    fail_connect(err);
    return;
  }
  // Reports and commands are small and periodic: sent at once, not coalesced.
  const int one = 1;
  ::setsockopt(fd_, IPPROTO_TCP, TCP_NODELAY, &one, sizeof one);
  connecting_ = false;
  ++counters_.connects;
  new_connection_ = true;
  last_byte_ns_ = steady_now_ns();
}

std::vector<uint8_t> TcpClient::read(double timeout_s) {
  std::vector<uint8_t> bytes;
  const int64_t deadline = steady_now_ns() + seconds_to_ns(timeout_s);
  for (;;) {
    const int64_t now = steady_now_ns();
    if (fd_ < 0) {
      if (now >= next_connect_ns_) {
        start_connect();
        continue;
      }
      // Wait for the next connect or the deadline, whichever is first.
      const int64_t until = std::min(deadline, next_connect_ns_);
      if (until > now) ::poll(nullptr, 0, poll_timeout_ms(until - now));
      if (steady_now_ns() >= deadline) return bytes;
      continue;
    }
    if (connecting_) {
      finish_connect(
          poll_timeout_ms(std::max<int64_t>(0, std::min(deadline, connect_deadline_ns_) - now)));
      if (!connected() && steady_now_ns() >= deadline) return bytes;
      continue;
    }
    const int64_t idle_at = last_byte_ns_ + seconds_to_ns(params_.idle_timeout_s);
    if (now >= idle_at) {
      drop("no byte from " + address_ + " for " + std::to_string(params_.idle_timeout_s) + " s",
           true);
      continue;
    }
    int err = 0;
    switch (detail::read_some(fd_, std::min(deadline, idle_at), bytes, &err)) {
      case detail::FdRead::kBytes:
        counters_.bytes_received += bytes.size();
        last_byte_ns_ = steady_now_ns();
        return bytes;
      case detail::FdRead::kClosed:
        drop(address_ + " closed the connection", false);
        break;
      case detail::FdRead::kFailed:
        drop("read from " + address_ + ": " + std::strerror(err), false);
        break;
      case detail::FdRead::kTimeout:
        break;
    }
    if (steady_now_ns() >= deadline) return bytes;
  }
}

bool TcpClient::write(std::string_view bytes) {
  if (!connected()) return false;
  int err = 0;
  if (detail::write_all(fd_, bytes, true, poll_timeout_ms(seconds_to_ns(params_.connect_timeout_s)),
                        &err)) {
    return true;
  }
  drop("send to " + address_ + ": " + std::strerror(err), false);
  return false;
}

bool TcpClient::take_new_connection() {
  return std::exchange(new_connection_, false);
}

}  // namespace pensight
