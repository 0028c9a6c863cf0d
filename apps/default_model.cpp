#include "apps/default_model.h"

#include <algorithm>
#include <cstdlib>
#include <system_error>
#include <vector>

#include "kernels/nn/nn_onnx.h"
#include "pipeline/depth/depth_input.h"

namespace pensight::app {

std::filesystem::path find_default_depth_model(const PinholeCamera& camera) {
  namespace fs = std::filesystem;
  std::vector<fs::path> dirs;
  if (const char* dir = std::getenv("PENSIGHT_MODEL_DIR")) dirs.emplace_back(dir);
  std::error_code ec;
  const fs::path exe = fs::read_symlink("/proc/self/exe", ec);
  if (!ec) dirs.push_back(exe.parent_path() / "../.." / kModelsDir);
  for (const fs::path& dir : dirs) {
    std::vector<fs::path> files;
    for (const auto& e : fs::directory_iterator(dir, ec)) {
      const std::string name = e.path().filename().string();
      if (e.is_regular_file() && name.starts_with("compact_depth") && name.ends_with(".onnx")) {
        files.push_back(e.path());
      }
    }
    std::sort(files.begin(), files.end());
    fs::path best;
    double best_share = -1;
    for (const fs::path& f : files) {
      try {
        const kernels::Graph g = kernels::import_onnx(f);
        if (g.inputs().empty() || g.value(g.inputs()[0]).shape.size() != 4) continue;
        const kernels::Dims& d = g.value(g.inputs()[0]).shape;
        const NetworkView v = network_view(camera.width_px, camera.height_px,
                                           static_cast<int>(d[3]), static_cast<int>(d[2]));
        const double share = static_cast<double>(v.width_px) * v.height_px /
                             (static_cast<double>(camera.width_px) * camera.height_px);
        if (share > best_share) best = f, best_share = share;
      } catch (const std::exception&) {
        // Not a model this build reads: the next one may be; --model names one explicitly.
      }
    }
    if (!best.empty()) return fs::weakly_canonical(best, ec);
  }
  return {};
}

}  // namespace pensight::app
