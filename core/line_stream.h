#pragma once
// A byte stream cut into text lines, as line-oriented devices send them (Water Linked's TCP JSON
// reports, its serial sentences, NMEA) and their clients send commands (TcpServer): a line ends at
// '\n' or '\r' (so "\r\n" and a bare '\r' both end one; the empty line between them is not
// returned). Bytes may arrive in any chunking. A line longer than max_line_bytes is a corrupt or
// foreign stream: its bytes up to the next end are dropped and counted, so memory stays bounded.
// Cost: O(bytes).
#include <cstddef>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

namespace pensight {

struct LineStreamCounters {
  size_t lines = 0;           // returned
  size_t overlong_lines = 0;  // dropped for their length
};

class LineStream {
 public:
  // The largest Water Linked report (a velocity report with its covariance and four transducers)
  // is ~1.1 kB; 64 KiB leaves room for any configuration reply.
  explicit LineStream(size_t max_line_bytes = 65536) : max_line_bytes_(max_line_bytes) {}

  // The complete lines these bytes finish, without their end; an unfinished one is kept.
  std::vector<std::string> feed(std::span<const uint8_t> bytes);
  // Forgets an unfinished line: the connection it came on is gone.
  void discard_unfinished() {
    pending_.clear();
    dropping_ = false;
  }
  const LineStreamCounters& counters() const { return counters_; }

 private:
  size_t max_line_bytes_;
  std::string pending_;
  bool dropping_ = false;  // inside an overlong line: its bytes are passed over to its end
  LineStreamCounters counters_;
};

}  // namespace pensight
