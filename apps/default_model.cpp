#include "apps/default_model.h"

#include <cstdlib>
#include <system_error>
#include <vector>

namespace pensight::app {

std::filesystem::path find_default_depth_model() {
  namespace fs = std::filesystem;
  const fs::path name = fs::path(kDefaultDepthModel).filename();
  std::vector<fs::path> candidates;
  if (const char* dir = std::getenv("PENSIGHT_MODEL_DIR"))
    candidates.push_back(fs::path(dir) / name);
  std::error_code ec;
  const fs::path exe = fs::read_symlink("/proc/self/exe", ec);
  if (!ec) candidates.push_back(exe.parent_path() / "../.." / kDefaultDepthModel);
  for (const fs::path& c : candidates) {
    if (fs::is_regular_file(c, ec)) return fs::weakly_canonical(c, ec);
  }
  return {};
}

}  // namespace pensight::app
