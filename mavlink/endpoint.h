#pragma once
// Where a MAVLink link sends and listens, in MAVProxy's notation, and its connection.
// "udpout:HOST:PORT" sends to HOST:PORT (a vehicle's or router's listening port);
// "udpin:ADDR:PORT" listens on ADDR:PORT (0.0.0.0: every interface) and replies to whoever sent
// to it last, as BlueOS and mavlink-router expect of a ground station; "tcp:HOST:PORT" connects to
// a TCP server (ArduSub SITL's 5760, BlueOS's internal link 5777) and reconnects when it drops.
#include <cstdint>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "core/tcp_client.h"

namespace pensight::mavlink {

struct Endpoint {
  enum class Kind { kUdpOut, kUdpIn, kTcp };
  Kind kind = Kind::kUdpOut;
  std::string text;   // as given, for messages
  std::string host;   // as given
  uint32_t ipv4 = 0;  // the host, resolved, in host byte order
  uint16_t port = 0;  // 0 only for udpin: the system picks one (UdpSocket::local_port)
};

// Parses and resolves an endpoint. Throws pensight::Error naming `text` and the accepted forms
// for an unknown scheme, a missing host, a missing or invalid port (1..65535; 0 also for udpin),
// or a host that does not resolve to an IPv4 address.
Endpoint parse_endpoint(const std::string& text);

class UdpSocket {
 public:
  // Opens the socket: udpout connects it to the endpoint (so the kernel reports an unreachable
  // peer as a socket error), udpin binds it. Throws pensight::Error naming the endpoint when the
  // socket cannot be opened, bound or connected.
  explicit UdpSocket(const Endpoint& endpoint);
  ~UdpSocket();
  UdpSocket(const UdpSocket&) = delete;
  UdpSocket& operator=(const UdpSocket&) = delete;

  // Sends one datagram to the peer: the endpoint (udpout) or the last sender (udpin). False when
  // it was not sent: a failure (counted in errors(), never thrown) or, on udpin, no one has sent
  // to us yet (not counted).
  bool send(std::span<const uint8_t> datagram);

  // Appends every datagram waiting to `bytes`; never blocks. Errors are counted, not thrown.
  void receive(std::vector<uint8_t>& bytes);

  // Send and socket errors so far (an ECONNREFUSED of an earlier send shows up on either call).
  uint64_t errors() const { return errors_; }
  uint16_t local_port() const;

 private:
  const Endpoint endpoint_;
  int fd_ = -1;
  bool has_peer_ = false;
  uint32_t peer_ipv4_ = 0;
  uint16_t peer_port_ = 0;
  uint64_t errors_ = 0;
  std::vector<uint8_t> datagram_;  // the largest UDP datagram
};

// A link's bytes over any endpoint: UDP datagrams, or a TCP stream kept connected by TcpClient
// (a refused or lost connection is retried every 0.5 s and counted as an error). Never blocks.
class Connection {
 public:
  // Throws pensight::Error as UdpSocket does, or naming a TCP endpoint's host that does not
  // resolve.
  explicit Connection(const Endpoint& endpoint);
  ~Connection();
  Connection(const Connection&) = delete;
  Connection& operator=(const Connection&) = delete;

  // False when not sent: a failure (counted in errors()), no peer yet (udpin), or no TCP
  // connection at the moment.
  bool send(std::span<const uint8_t> bytes);
  // Appends every byte waiting to `bytes` (TCP: starts or finishes a connect when due).
  void receive(std::vector<uint8_t>& bytes);
  // UDP: send and socket errors; TCP: failed connects and dropped connections.
  uint64_t errors() const;
  // The local UDP port (0 for TCP).
  uint16_t local_port() const;

 private:
  std::unique_ptr<UdpSocket> udp_;
  std::unique_ptr<TcpClient> tcp_;
};

}  // namespace pensight::mavlink
