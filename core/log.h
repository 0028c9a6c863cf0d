#pragma once
// Minimal process-wide logging. The embedding application may redirect it with set_log_sink.
#include <functional>
#include <string_view>

namespace pensight {

enum class LogLevel { kDebug, kInfo, kWarning, kError };

using LogSink = std::function<void(LogLevel, std::string_view)>;

// Replaces the sink (default: stderr, "pensight: " prefix, info and above). Thread-safe.
void set_log_sink(LogSink sink);
void log(LogLevel level, std::string_view message);

inline void log_info(std::string_view m) {
  log(LogLevel::kInfo, m);
}
inline void log_warning(std::string_view m) {
  log(LogLevel::kWarning, m);
}
inline void log_error(std::string_view m) {
  log(LogLevel::kError, m);
}

}  // namespace pensight
