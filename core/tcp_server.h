#pragma once
// A TCP listener for the device stand-ins (`pensight sim-devices`): it accepts any number of
// clients and broadcasts a device's stream to all of them, as a Water Linked DVL or a camera
// encoder does; what clients send comes back as lines. A client that goes away or stops reading
// for longer than the send wait is dropped and counted. Clients are named by an id that stays
// theirs while connected. Non-blocking, one thread uses it.
#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "core/line_stream.h"

namespace pensight {

class TcpServer {
 public:
  // Listens on host:port (port 0: an ephemeral one, see port()). Throws pensight::Error naming
  // the address when it cannot resolve or bind (in use: another stand-in or the device itself).
  TcpServer(const std::string& host, int port, int send_wait_ms = 1000);
  ~TcpServer();
  TcpServer(const TcpServer&) = delete;
  TcpServer& operator=(const TcpServer&) = delete;

  int port() const { return port_; }
  // Accepts the clients waiting to connect; returns their ids.
  std::vector<uint64_t> accept_new();
  // Sends `bytes` to every client (those that fail are dropped).
  void broadcast(std::string_view bytes);
  // Sends `bytes` to one client (dropped when it fails); nothing when it is gone.
  void send_to(uint64_t client, std::string_view bytes);
  // The complete lines (LineStream's) each client sent since the last call, with its id; clients
  // that went away are dropped.
  std::vector<std::pair<uint64_t, std::string>> take_lines();
  // Closes every client's connection (a device that restarts), counted as dropped.
  void disconnect_all();
  size_t clients() const { return clients_.size(); }
  uint64_t dropped_clients() const { return dropped_; }

 private:
  struct Client {
    uint64_t id = 0;
    int fd = -1;
    LineStream lines;
  };
  void drop(size_t index);
  bool send_at(size_t index, std::string_view bytes);  // false: failed and dropped

  int fd_ = -1;
  int port_ = 0;
  int send_wait_ms_;
  std::vector<Client> clients_;
  uint64_t dropped_ = 0;
  uint64_t next_id_ = 1;
};

}  // namespace pensight
