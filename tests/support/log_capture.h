#pragma once
// Captures pensight's log for the duration of a test, one message per line, from any thread.
#include <mutex>
#include <string>
#include <string_view>

#include "core/log.h"

namespace pensight::testing {

class LogCapture {
 public:
  // Keeps messages of `min_level` and above.
  explicit LogCapture(LogLevel min_level = LogLevel::kDebug) {
    set_log_sink([this, min_level](LogLevel level, std::string_view m) {
      if (level < min_level) return;
      std::lock_guard lock(mutex_);
      text_ += std::string(m) + "\n";
    });
  }
  ~LogCapture() { set_log_sink(nullptr); }
  LogCapture(const LogCapture&) = delete;
  LogCapture& operator=(const LogCapture&) = delete;

  std::string text() const {
    std::lock_guard lock(mutex_);
    return text_;
  }

 private:
  mutable std::mutex mutex_;
  std::string text_;
};

}  // namespace pensight::testing
