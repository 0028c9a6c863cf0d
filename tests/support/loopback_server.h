#pragma once
// A TCP listener on 127.0.0.1 (an ephemeral port) for the tests' stand-in devices, and the few
// blocking calls a stand-in needs. Header-only, POSIX sockets.
#include <arpa/inet.h>
#include <netinet/in.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <gtest/gtest.h>

#include <cstdint>
#include <span>
#include <string>

namespace pensight::testing {

class LoopbackServer {
 public:
  LoopbackServer() {
    fd_ = ::socket(AF_INET, SOCK_STREAM, 0);
    sockaddr_in a{};
    a.sin_family = AF_INET;
    a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    EXPECT_EQ(::bind(fd_, reinterpret_cast<sockaddr*>(&a), sizeof a), 0);
    EXPECT_EQ(::listen(fd_, 4), 0);
    socklen_t len = sizeof a;
    ::getsockname(fd_, reinterpret_cast<sockaddr*>(&a), &len);
    port_ = ntohs(a.sin_port);
  }
  ~LoopbackServer() { ::close(fd_); }
  LoopbackServer(const LoopbackServer&) = delete;
  LoopbackServer& operator=(const LoopbackServer&) = delete;

  int port() const { return port_; }
  // The next client's connection (blocks until one connects).
  int accept_one() const { return ::accept(fd_, nullptr, nullptr); }

  // The next line the client sends, without its '\n' (waits up to 5 s for each byte).
  static std::string read_line(int conn) {
    std::string line;
    char c = 0;
    pollfd p{conn, POLLIN, 0};
    while (::poll(&p, 1, 5000) == 1 && ::recv(conn, &c, 1, 0) == 1 && c != '\n') line += c;
    return line;
  }
  static void send_all(int conn, std::span<const uint8_t> bytes) {
    size_t sent = 0;
    while (sent < bytes.size()) {
      const ssize_t n = ::send(conn, bytes.data() + sent, bytes.size() - sent, MSG_NOSIGNAL);
      ASSERT_GT(n, 0) << "the client went away";
      sent += static_cast<size_t>(n);
    }
  }
  static void send_all(int conn, const std::string& s) {
    send_all(conn, std::span(reinterpret_cast<const uint8_t*>(s.data()), s.size()));
  }

 private:
  int fd_ = -1;
  int port_ = 0;
};

}  // namespace pensight::testing
