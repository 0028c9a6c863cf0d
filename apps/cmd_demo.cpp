// The README's main command. Until the synthetic world and the pipeline land, the built-in job
// is the first kernel on a synthetic net-like frame: the 5x6 ROI grid normalised on the CPU and on
// the Vulkan device, with timings and the largest difference between the two.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <vector>

#include "apps/command.h"
#include "kernels/roi_normalize/roi_normalize.h"
#include "runtime/timing.h"
#include "runtime/vk_buffer.h"
#include "runtime/vk_context.h"

namespace pensight::app {
namespace {

// A square lattice of dark twine on a lighter background, 24 px period.
ImageU8 net_like_frame(int w, int h) {
  ImageU8 img(w, h);
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) {
      const bool twine = (x % 24) < 4 || (y % 24) < 4;
      img.at(x, y) = static_cast<uint8_t>(twine ? 60 : 170 + (x * 7 + y * 3) % 20);
    }
  }
  return img;
}

std::vector<kernels::RoiOrigin> roi_grid(int w, int h, int rows, int cols, int size) {
  std::vector<kernels::RoiOrigin> rois;
  for (int r = 0; r < rows; ++r) {
    for (int c = 0; c < cols; ++c) {
      rois.push_back(
          {cols > 1 ? c * (w - size) / (cols - 1) : 0, rows > 1 ? r * (h - size) / (rows - 1) : 0});
    }
  }
  return rois;
}

}  // namespace

int cmd_demo(const Args&) {
  const kernels::RoiNormalizeShape shape{720, 540, 8, 300};
  const ImageU8 frame = net_like_frame(shape.width, shape.height);
  const auto rois = roi_grid(shape.width, shape.height, 5, 6, shape.roi_size);
  const size_t n = rois.size() * shape.roi_size * shape.roi_size;

  std::vector<float> cpu(n);
  Stopwatch sw;
  constexpr int kRuns = 10;
  for (int i = 0; i < kRuns; ++i) kernels::roi_normalize_cpu(frame, rois, shape.roi_size, cpu);
  const double cpu_ms = sw.elapsed_ms() / kRuns;
  std::printf("roi_normalize, 30 ROIs of 300 px on 720x540:\n");
  std::printf("  cpu reference        %8.3f ms/frame\n", cpu_ms);

  const vk::Context ctx;
  const kernels::RoiNormalizeVk kernel(ctx, shape);
  vk::Buffer image(ctx, kernel.image_bytes());
  vk::Buffer origins(ctx, rois.size() * sizeof(kernels::RoiOrigin));
  origins.upload(rois.data(), rois.size() * sizeof(kernels::RoiOrigin));
  vk::TypedBuffer<float> out(ctx, n);
  vk::CommandStream stream(ctx);
  kernel.record(stream, image, origins, out.raw(), static_cast<uint32_t>(rois.size()));
  sw.restart();
  for (int i = 0; i < kRuns; ++i) {
    image.upload(frame.pixels.data(), frame.pixels.size());
    stream.submit_and_wait();
  }
  const double vk_ms = sw.elapsed_ms() / kRuns;
  const auto gpu = out.to_vector();
  float max_diff = 0;
  for (size_t i = 0; i < n; ++i) max_diff = std::max(max_diff, std::abs(gpu[i] - cpu[i]));
  std::printf("  vulkan (%s) %8.3f ms/frame (device %.3f ms), max |vk - cpu| = %.2e\n",
              ctx.info().name.c_str(), vk_ms,
              stream.timings().empty() ? NAN : stream.timings()[0].device_ms, max_diff);
  return max_diff < 1e-3f ? 0 : 1;
}

PENSIGHT_COMMAND("demo", "run the built-in default job and print timing and accuracy", cmd_demo);

}  // namespace pensight::app
