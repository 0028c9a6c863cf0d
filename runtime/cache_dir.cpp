#include "runtime/cache_dir.h"

#include <cstdlib>

#include "core/atomic_file.h"
#include "core/error.h"

namespace pensight {
namespace {

std::string env(const char* name) {
  const char* v = std::getenv(name);
  return v ? v : "";
}

}  // namespace

std::filesystem::path cache_dir() {
  if (const std::string dir = env("PENSIGHT_CACHE_DIR"); !dir.empty()) return dir;
  if (const std::string xdg = env("XDG_CACHE_HOME"); !xdg.empty()) {
    return std::filesystem::path(xdg) / "pensight";
  }
  if (const std::string home = env("HOME"); !home.empty()) {
    return std::filesystem::path(home) / ".cache" / "pensight";
  }
  return {};
}

void write_cache_file(const std::filesystem::path& path, std::string_view bytes) {
  std::error_code ec;
  std::filesystem::create_directories(path.parent_path(), ec);
  try {
    write_file_atomically(path, bytes);
  } catch (const Error&) {
    // A read-only home or a full disk: the cache is an optimisation, not worth an error.
  }
}

}  // namespace pensight
