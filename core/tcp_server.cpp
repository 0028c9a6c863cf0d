#include "core/tcp_server.h"

#include <arpa/inet.h>
#include <fcntl.h>
#include <netinet/in.h>
#include <netinet/tcp.h>
#include <sys/socket.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

#include "core/error.h"
#include "core/internal/fd_io.h"
#include "core/tcp_client.h"
#include "core/timing.h"

namespace pensight {

TcpServer::TcpServer(const std::string& host, int port, int send_wait_ms)
    : send_wait_ms_(send_wait_ms) {
  const std::string address = host + ":" + std::to_string(port);
  std::string why;
  const std::optional<uint32_t> ip = resolve_ipv4(host, &why);
  if (!ip) throw Error("cannot listen on " + address + ": " + why);
  if (port < 0 || port > 65535)
    throw Error("cannot listen on " + address + ": port outside 0..65535");
  fd_ = ::socket(AF_INET, SOCK_STREAM | SOCK_NONBLOCK | SOCK_CLOEXEC, 0);
  if (fd_ < 0) throw Error("cannot listen on " + address + ": " + std::strerror(errno));
  const int one = 1;
  ::setsockopt(fd_, SOL_SOCKET, SO_REUSEADDR, &one, sizeof one);
  sockaddr_in a{};
  a.sin_family = AF_INET;
  a.sin_addr.s_addr = htonl(*ip);
  a.sin_port = htons(static_cast<uint16_t>(port));
  if (::bind(fd_, reinterpret_cast<sockaddr*>(&a), sizeof a) != 0 || ::listen(fd_, 8) != 0) {
    const std::string reason = std::strerror(errno);
    ::close(fd_);
    throw Error("cannot listen on " + address + ": " + reason +
                " (is the device, or another stand-in, already there?)");
  }
  socklen_t len = sizeof a;
  ::getsockname(fd_, reinterpret_cast<sockaddr*>(&a), &len);
  port_ = ntohs(a.sin_port);
}

TcpServer::~TcpServer() {
  for (const Client& c : clients_) ::close(c.fd);
  ::close(fd_);
}

std::vector<uint64_t> TcpServer::accept_new() {
  std::vector<uint64_t> added;
  for (;;) {
    const int c = ::accept4(fd_, nullptr, nullptr, SOCK_NONBLOCK | SOCK_CLOEXEC);
    if (c < 0) return added;
    const int one = 1;
    ::setsockopt(c, IPPROTO_TCP, TCP_NODELAY, &one, sizeof one);
    clients_.push_back({next_id_, c, LineStream()});
    added.push_back(next_id_++);
  }
}

void TcpServer::drop(size_t index) {
  ::close(clients_[index].fd);
  clients_.erase(clients_.begin() + static_cast<ptrdiff_t>(index));
  ++dropped_;
}

void TcpServer::disconnect_all() {
  while (!clients_.empty()) drop(clients_.size() - 1);
}

bool TcpServer::send_at(size_t index, std::string_view bytes) {
  int error = 0;
  if (detail::write_all(clients_[index].fd, bytes, true, send_wait_ms_, &error)) return true;
  drop(index);
  return false;
}

void TcpServer::send_to(uint64_t client, std::string_view bytes) {
  for (size_t i = 0; i < clients_.size(); ++i) {
    if (clients_[i].id == client) {
      send_at(i, bytes);
      return;
    }
  }
}

void TcpServer::broadcast(std::string_view bytes) {
  for (size_t i = clients_.size(); i-- > 0;) send_at(i, bytes);
}

std::vector<std::pair<uint64_t, std::string>> TcpServer::take_lines() {
  std::vector<std::pair<uint64_t, std::string>> lines;
  for (size_t i = clients_.size(); i-- > 0;) {
    std::vector<uint8_t> bytes;
    int error = 0;
    const detail::FdRead r = detail::read_some(clients_[i].fd, steady_now_ns(), bytes, &error);
    for (std::string& line : clients_[i].lines.feed(bytes)) {
      lines.emplace_back(clients_[i].id, std::move(line));
    }
    if (r == detail::FdRead::kClosed || r == detail::FdRead::kFailed) drop(i);
  }
  return lines;
}

}  // namespace pensight
