#include "mavlink/endpoint.h"

#include <arpa/inet.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <memory>

#include "core/error.h"

namespace pensight::mavlink {
namespace {

constexpr size_t kMaxDatagram = 65536;

[[noreturn]] void fail(const std::string& text, const std::string& why) {
  throw Error("MAVLink endpoint '" + text + "': " + why +
              "; use udpout:HOST:PORT (send to HOST), udpin:ADDR:PORT (listen on ADDR, 0.0.0.0 "
              "for every interface) or tcp:HOST:PORT (connect to a TCP server: ArduSub SITL 5760, "
              "BlueOS 5777)");
}

uint16_t parse_port(const std::string& text, const std::string& port, bool zero_allowed) {
  const bool digits = !port.empty() && port.size() <= 5 &&
                      port.find_first_not_of("0123456789") == std::string::npos;
  const unsigned long value = digits ? std::stoul(port) : 0;
  if (!digits || value > 65535 || (value == 0 && !zero_allowed)) {
    fail(text, "port '" + port + "' is not a number in 1..65535");
  }
  return static_cast<uint16_t>(value);
}

sockaddr_in to_sockaddr(uint32_t ipv4, uint16_t port) {
  sockaddr_in a{};
  a.sin_family = AF_INET;
  a.sin_addr.s_addr = htonl(ipv4);
  a.sin_port = htons(port);
  return a;
}

}  // namespace

Endpoint parse_endpoint(const std::string& text) {
  Endpoint e;
  e.text = text;
  const size_t colon = text.find(':');
  const std::string scheme = text.substr(0, colon);
  if (scheme == "udpout") {
    e.kind = Endpoint::Kind::kUdpOut;
  } else if (scheme == "udpin") {
    e.kind = Endpoint::Kind::kUdpIn;
  } else if (scheme == "tcp") {
    e.kind = Endpoint::Kind::kTcp;
  } else {
    fail(text, "unknown scheme '" + scheme + "'");
  }
  const std::string rest = colon == std::string::npos ? "" : text.substr(colon + 1);
  const size_t port_colon = rest.rfind(':');
  if (port_colon == std::string::npos) fail(text, "no port");
  const std::string host = rest.substr(0, port_colon);
  if (host.empty()) fail(text, "no host");
  e.host = host;
  e.port = parse_port(text, rest.substr(port_colon + 1), e.kind == Endpoint::Kind::kUdpIn);
  std::string why;
  const std::optional<uint32_t> ipv4 = resolve_ipv4(host, &why);
  if (!ipv4) fail(text, "host '" + host + "' does not resolve to an IPv4 address (" + why + ")");
  e.ipv4 = *ipv4;
  return e;
}

UdpSocket::UdpSocket(const Endpoint& endpoint) : endpoint_(endpoint), datagram_(kMaxDatagram) {
  fd_ = ::socket(AF_INET, SOCK_DGRAM | SOCK_NONBLOCK | SOCK_CLOEXEC, 0);
  if (fd_ < 0) {
    throw Error("MAVLink endpoint '" + endpoint_.text + "': cannot open a UDP socket (" +
                std::strerror(errno) + ")");
  }
  const sockaddr_in a = to_sockaddr(endpoint_.ipv4, endpoint_.port);
  const bool in = endpoint_.kind == Endpoint::Kind::kUdpIn;
  const auto* addr = reinterpret_cast<const sockaddr*>(&a);
  if ((in ? ::bind(fd_, addr, sizeof a) : ::connect(fd_, addr, sizeof a)) != 0) {
    const int error = errno;
    ::close(fd_);
    throw Error("MAVLink endpoint '" + endpoint_.text + "': cannot " +
                (in ? "listen there (" : "send there (") + std::strerror(error) +
                "); for udpin give an address of this machine and a port no other program uses");
  }
}

UdpSocket::~UdpSocket() {
  ::close(fd_);
}

bool UdpSocket::send(std::span<const uint8_t> datagram) {
  ssize_t sent = 0;
  if (endpoint_.kind == Endpoint::Kind::kUdpOut) {
    sent = ::send(fd_, datagram.data(), datagram.size(), MSG_NOSIGNAL);
  } else {
    if (!has_peer_) return false;
    const sockaddr_in to = to_sockaddr(peer_ipv4_, peer_port_);
    sent = ::sendto(fd_, datagram.data(), datagram.size(), MSG_NOSIGNAL,
                    reinterpret_cast<const sockaddr*>(&to), sizeof to);
  }
  if (sent == static_cast<ssize_t>(datagram.size())) return true;
  ++errors_;
  return false;
}

void UdpSocket::receive(std::vector<uint8_t>& bytes) {
  for (;;) {
    sockaddr_in from{};
    socklen_t from_size = sizeof from;
    const ssize_t n = ::recvfrom(fd_, datagram_.data(), datagram_.size(), 0,
                                 reinterpret_cast<sockaddr*>(&from), &from_size);
    if (n < 0) {
      // Nothing more waiting is the normal end; anything else (ECONNREFUSED after a send to a
      // closed port) is counted, and the next call reads on.
      if (errno != EAGAIN && errno != EWOULDBLOCK) ++errors_;
      return;
    }
    bytes.insert(bytes.end(), datagram_.begin(), datagram_.begin() + n);
    if (endpoint_.kind == Endpoint::Kind::kUdpIn) {
      has_peer_ = true;
      peer_ipv4_ = ntohl(from.sin_addr.s_addr);
      peer_port_ = ntohs(from.sin_port);
    }
  }
}

uint16_t UdpSocket::local_port() const {
  sockaddr_in a{};
  socklen_t size = sizeof a;
  ::getsockname(fd_, reinterpret_cast<sockaddr*>(&a), &size);
  return ntohs(a.sin_port);
}

Connection::Connection(const Endpoint& endpoint) {
  if (endpoint.kind == Endpoint::Kind::kTcp) {
    tcp_ = std::make_unique<TcpClient>(endpoint.host, endpoint.port);
  } else {
    udp_ = std::make_unique<UdpSocket>(endpoint);
  }
}

Connection::~Connection() = default;

bool Connection::send(std::span<const uint8_t> bytes) {
  if (udp_) return udp_->send(bytes);
  // Not connected: receive() starts and finishes the connect.
  return tcp_->write({reinterpret_cast<const char*>(bytes.data()), bytes.size()});
}

void Connection::receive(std::vector<uint8_t>& bytes) {
  if (udp_) {
    udp_->receive(bytes);
    return;
  }
  for (std::vector<uint8_t> got = tcp_->read(0); !got.empty(); got = tcp_->read(0)) {
    bytes.insert(bytes.end(), got.begin(), got.end());
  }
}

uint64_t Connection::errors() const {
  if (udp_) return udp_->errors();
  return tcp_->counters().connect_failures + tcp_->counters().drops +
         tcp_->counters().idle_timeouts;
}

uint16_t Connection::local_port() const {
  return udp_ ? udp_->local_port() : 0;
}

}  // namespace pensight::mavlink
