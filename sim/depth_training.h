#pragma once
// Training data for the depth-completion network (scripts/train_depth.sh): random one-frame
// scenes of the net-pen world, rendered, run through the FFT detector for their priors (the
// detector's own, with its real noise, not truth samples), and stored at the network's resolution
// with the rendered ground-truth depth.
//
// Folder layout, read by scripts/train_depth.py (N samples, W x H = 320 x 240, K = max_points):
//   depth_data.txt   "key: value" lines: version (2), samples, width, height, max_points, sigma_px,
//                    seed, samples_without_priors
//   image.u8         N*H*W grey levels (depth_input.h resize_area of the camera frame)
//   depth_mm.u16     N*H*W ground-truth z-depth of the net in mm, 0 = no net (water, fish, ...)
//   points.f32       N*K*4 (x_px, y_px, depth_m, quality) in network pixels, unused slots 0
//   num_points.i32   N point counts
//   wall.f32         N*2 (curvature_per_m, focal_px): the net wall's curvature (1 / the pen's
//                    radius, 0 for a flat panel) and the focal length in network pixels, as the
//                    depth stage's prior surface takes them (prior_surface.h NetWallShape)
// Little-endian, row-major. Samples are independent: sample i depends only on (seed, i).
#include <cstdint>
#include <filesystem>
#include <functional>
#include <vector>

#include "core/image.h"
#include "pipeline/depth/prior_surface.h"
#include "pipeline/fft/net_geometry.h"
#include "sim/scenario.h"

namespace pensight::sim {

// A one-frame scenario drawn from the training distribution: cylinder pens of 6-25 m and flat
// tank panels; the camera 0.3-5 m from the net (log-uniform), heading +-35 deg, pitch +-20 deg,
// at times near the bottom looking down or near the surface; water from clear to turbid; daylight
// and lamp-lit night; square and diamond meshes of 15-45 mm with thin to thick twines, knots,
// fouling, ropes and bulges; fish in front of the net; defocus and JPEG. Valid (sim::validate).
Scenario random_depth_scene(uint64_t seed);

struct DepthSample {
  ImageU8 image;                    // network resolution
  ImageU16 depth_mm;                // network resolution, 0 = no net
  std::vector<SparseDepth> points;  // network pixels; empty when the FFT pose was NaN
  NetWallShape wall;                // in network pixels
};

// Renders random_depth_scene(seed) with the CPU renderer and runs the CPU FFT detector on it.
DepthSample make_depth_sample(uint64_t seed, int width, int height);

struct DepthDataOptions {
  int samples = 0;
  uint64_t seed = 1;
  int width = 320, height = 240;
  int threads = 0;  // 0: all hardware threads
  std::function<void(int done, int total)> progress;
};

// Writes the folder `out` (replacing an earlier training-data folder there, never another
// folder); nothing appears there unless every sample was written. Throws pensight::Error naming
// the path on a write error.
void write_depth_data(const std::filesystem::path& out, const DepthDataOptions& options);

}  // namespace pensight::sim
