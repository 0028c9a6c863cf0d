#include "core/internal/fd_io.h"

#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>

#include "core/timing.h"

namespace pensight::detail {

FdRead read_some(int fd, int64_t wait_until_ns, std::vector<uint8_t>& bytes, int* error) {
  pollfd p{fd, POLLIN, 0};
  const int rc =
      ::poll(&p, 1, poll_timeout_ms(std::max<int64_t>(0, wait_until_ns - steady_now_ns())));
  if (rc < 0 && errno != EINTR) {
    *error = errno;
    return FdRead::kFailed;
  }
  if (rc <= 0) return FdRead::kTimeout;
  uint8_t buf[4096];
  const ssize_t n = ::read(fd, buf, sizeof buf);
  if (n > 0) {
    bytes.insert(bytes.end(), buf, buf + n);
    return FdRead::kBytes;
  }
  if (n == 0) return FdRead::kClosed;
  if (errno == EAGAIN || errno == EWOULDBLOCK || errno == EINTR) return FdRead::kTimeout;
  *error = errno;
  return FdRead::kFailed;
}

bool write_all(int fd, std::string_view bytes, bool socket, int wait_ms, int* error) {
  size_t sent = 0;
  while (sent < bytes.size()) {
    const ssize_t n = socket ? ::send(fd, bytes.data() + sent, bytes.size() - sent, MSG_NOSIGNAL)
                             : ::write(fd, bytes.data() + sent, bytes.size() - sent);
    if (n > 0) {
      sent += static_cast<size_t>(n);
      continue;
    }
    if (n < 0 && errno == EINTR) continue;
    if (n < 0 && (errno == EAGAIN || errno == EWOULDBLOCK)) {
      pollfd p{fd, POLLOUT, 0};
      if (::poll(&p, 1, wait_ms) == 1) continue;
      *error = EAGAIN;
      return false;
    }
    *error = n < 0 ? errno : EIO;
    return false;
  }
  return true;
}

}  // namespace pensight::detail
