#pragma once
// The byte I/O that TcpClient and SerialPort share on an open, non-blocking descriptor; each keeps
// its own state machine (connect or open, reconnect, idle timeout) and its own messages.
#include <cstdint>
#include <string_view>
#include <vector>

namespace pensight::detail {

enum class FdRead {
  kBytes,    // bytes were appended
  kTimeout,  // none came by wait_until_ns
  kClosed,   // the peer closed the connection (a read of 0 bytes)
  kFailed,   // poll or read failed: *error holds errno (EIO: a terminal hung up)
};

// Waits for bytes on fd until wait_until_ns (steady clock) and appends what one read returns.
FdRead read_some(int fd, int64_t wait_until_ns, std::vector<uint8_t>& bytes, int* error);

// Writes all of `bytes` (a socket with MSG_NOSIGNAL), waiting up to wait_ms for room each time it
// is full; false with *error set when it fails or stays full.
bool write_all(int fd, std::string_view bytes, bool socket, int wait_ms, int* error);

}  // namespace pensight::detail
