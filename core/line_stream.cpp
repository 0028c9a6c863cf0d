#include "core/line_stream.h"

namespace pensight {

std::vector<std::string> LineStream::feed(std::span<const uint8_t> bytes) {
  std::vector<std::string> lines;
  for (const uint8_t b : bytes) {
    if (b == '\n' || b == '\r') {
      if (dropping_) {
        dropping_ = false;
      } else if (!pending_.empty()) {
        lines.push_back(std::move(pending_));
        ++counters_.lines;
      }
      pending_.clear();
      continue;
    }
    if (dropping_) continue;
    if (pending_.size() >= max_line_bytes_) {
      dropping_ = true;
      pending_.clear();
      ++counters_.overlong_lines;
      continue;
    }
    pending_.push_back(static_cast<char>(b));
  }
  return lines;
}

}  // namespace pensight
