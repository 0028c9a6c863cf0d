#include "fuzz/fuzz_input.h"

#include <unistd.h>

#include <cstdlib>
#include <fstream>
#include <string_view>

#include "core/log.h"

namespace pensight::fuzz {
namespace fs = std::filesystem;

namespace {

struct WorkDir {
  fs::path path;
  WorkDir() {
    const char* tmp = std::getenv("TMPDIR");
    path =
        fs::path(tmp != nullptr ? tmp : "/tmp") / ("pensight_fuzz_" + std::to_string(::getpid()));
    fs::create_directories(path);
  }
  ~WorkDir() {
    std::error_code ignored;
    fs::remove_all(path, ignored);
  }
};

}  // namespace

const fs::path& work_dir() {
  static const WorkDir dir;
  return dir.path;
}

fs::path write_input(const uint8_t* data, size_t size, const std::string& name) {
  const fs::path file = work_dir() / name;
  fs::create_directories(file.parent_path());
  std::ofstream out(file, std::ios::binary | std::ios::trunc);
  out.write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(size));
  return file;
}

void quiet_log() {
  set_log_sink([](LogLevel, std::string_view) {});
}

}  // namespace pensight::fuzz
