#include "core/log.h"

#include <cstdio>
#include <mutex>
#include <string>

namespace pensight {
namespace {

std::mutex& sink_mutex() {
  static std::mutex m;
  return m;
}

LogSink& sink() {
  static LogSink s = [](LogLevel level, std::string_view message) {
    if (level == LogLevel::kDebug) return;
    const char* tag = level == LogLevel::kWarning ? "warning: "
                      : level == LogLevel::kError ? "error: "
                                                  : "";
    std::fprintf(stderr, "pensight: %s%.*s\n", tag, static_cast<int>(message.size()),
                 message.data());
  };
  return s;
}

}  // namespace

void set_log_sink(LogSink s) {
  std::lock_guard lock(sink_mutex());
  sink() = std::move(s);
}

void log(LogLevel level, std::string_view message) {
  std::lock_guard lock(sink_mutex());
  if (sink()) sink()(level, message);
}

}  // namespace pensight
