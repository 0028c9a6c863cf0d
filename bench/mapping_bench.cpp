// Occupancy mapping at 2 cm from 720x540 ground-truth depth (sim/truth_depth.h) and the true
// camera poses of the shipped sequences, side by side on the same images: our projective
// integrator (mapping/projective_integrator.h), the plain per-pixel ray caster
// (mapping/raycast_integrator.h) and, where a wavemap install is named (PENSIGHT_WAVEMAP_DIR),
// wavemap's hashed chunked wavelet integrator (bench/mapping/wavemap_peer.h). Every iteration
// integrates the frames in order into a fresh map; the time is the integration calls alone.
// Args: seq (0 follow.yaml, net at ~0.5 m; 1 sweep.yaml, net up to 5 m), frames (0: all).
// Both integrators that run in parallel get 2 threads, the product's two cores.
//
// Floor per frame: the depth image read (720 x 540 x 4 B = 1.56 MB) plus 4 B per voxel updated;
// docs/performance.md compares it with the memory bandwidth.
#include <benchmark/benchmark.h>
#include <tbb/global_control.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <functional>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "bench/process_cpu.h"
#include "mapping/map_io.h"
#include "mapping/projective_integrator.h"
#include "mapping/raycast_integrator.h"
#include "sim/frame_state.h"
#include "sim/scenario.h"
#include "sim/truth_depth.h"
#include "tools/evaluation/evaluation.h"
#if PENSIGHT_HAVE_WAVEMAP
#include "bench/mapping/wavemap_peer.h"
#endif

namespace {

using namespace pensight;
using bench::process_cpu_s;

constexpr int kThreads = 2;

struct Sequence {
  PinholeCamera camera;
  std::vector<ImageF32> depth_m;
  std::vector<Eigen::Isometry3d> T_pen_camera;
};

// Depth images and poses of every frame, made once per sequence.
const Sequence& sequence(int seq) {
  static std::map<int, Sequence> cache;
  auto it = cache.find(seq);
  if (it != cache.end()) return it->second;
  const char* root = std::getenv("PENSIGHT_SOURCE_DIR");
  const std::string file = seq == 0 ? "follow.yaml" : "sweep.yaml";
  const sim::Scenario s =
      sim::load_scenario(std::string(root ? root : PENSIGHT_SOURCE_DIR) + "/scenarios/" + file);
  const sim::NetGeometry net(s.pen, s.net);
  Sequence q;
  q.camera = s.camera.calibration.camera;
  const int frames = s.num_frames();
  q.depth_m.resize(frames);
  q.T_pen_camera.resize(frames);
  tbb::parallel_for(0, frames, [&](int f) {
    q.T_pen_camera[f] = sim::frame_state(s, f).T_pen_camera;
    q.depth_m[f] = sim::truth_depth(s, net, q.camera, q.T_pen_camera[f]);
  });
  return cache.emplace(seq, std::move(q)).first->second;
}

// What a map says around the measured points (every 16th pixel per axis of every integrated
// frame, within max range), read through the map's own log-odds query, so every integrator is
// scored alike:
// - surface_occupied: share of points whose ray reads occupied somewhere from half a voxel in
//   front of the point to 1.5 voxels behind it (the voxel holding a surface point may read free
//   and the one just behind it occupied);
// - surface_offset_voxel: median distance, in voxels, from the point to where the ray first reads
//   occupied (searched from 3 voxels in front to 3 behind, in quarter voxels);
// - front_occupied / front_free: share of the points 2 to 4 voxels in front of the surface,
//   along the ray, that read occupied (false occupancy) or free (cleared water).
struct MapQuality {
  double surface_occupied = 0, surface_offset_voxel = 0, front_occupied = 0, front_free = 0;
};
MapQuality map_quality(const Sequence& q, int frames, const mapping::MapConfig& config,
                       const std::function<float(const Eigen::Vector3d&)>& log_odds_at) {
  int points = 0, occupied = 0, front = 0, front_occ = 0, front_free = 0;
  std::vector<double> offsets;
  const double v = config.voxel_m;
  for (int f = 0; f < frames; ++f) {
    const ImageF32& depth = q.depth_m[f];
    const Eigen::Isometry3d& T = q.T_pen_camera[f];
    for (int y = 8; y < depth.height; y += 16) {
      for (int x = 8; x < depth.width; x += 16) {
        const float d = depth.at(x, y);
        if (!(d >= config.min_range_m && d <= config.max_range_m)) continue;
        const Eigen::Vector3d ray = T.linear() * q.camera.ray(Eigen::Vector2d(x, y));
        const Eigen::Vector3d p = T.translation() + ray * d, u = ray.normalized();
        ++points;
        for (const double k : {-0.5, 0.0, 0.5, 1.0, 1.5}) {
          if (log_odds_at(p + u * (k * v)) > 0) {
            ++occupied;
            break;
          }
        }
        for (double k = -3; k <= 3; k += 0.25) {
          if (log_odds_at(p + u * (k * v)) > 0) {
            offsets.push_back(std::abs(k));
            break;
          }
        }
        for (const double k : {-2.0, -3.0, -4.0}) {
          const float l = log_odds_at(p + u * (k * v));
          ++front;
          front_occ += l > 0;
          front_free += l < 0;
        }
      }
    }
  }
  MapQuality m;
  if (points == 0) return m;
  m.surface_occupied = static_cast<double>(occupied) / points;
  m.surface_offset_voxel = error_stats(offsets).median;  // 0 without offsets
  m.front_occupied = static_cast<double>(front_occ) / front;
  m.front_free = static_cast<double>(front_free) / front;
  return m;
}

void report_quality(benchmark::State& state, const MapQuality& m) {
  state.counters["surface_occupied"] = m.surface_occupied;
  state.counters["surface_offset_voxel"] = m.surface_offset_voxel;
  state.counters["front_occupied"] = m.front_occupied;
  state.counters["front_free"] = m.front_free;
}

// The benchmark loop: per iteration make_map() (untimed: the previous map is destroyed and a
// fresh one made), then integrate(map, depth, pose) per frame (timed); finish(map, sequence,
// frames) sees the last iteration's map.
template <class MakeMap, class Integrate, class Finish>
void run(benchmark::State& state, MakeMap&& make_map, Integrate&& integrate, Finish&& finish) {
  const Sequence& q = sequence(static_cast<int>(state.range(0)));
  const int all = static_cast<int>(q.depth_m.size());
  const int frames = state.range(1) > 0 ? std::min(static_cast<int>(state.range(1)), all) : all;
  double total_s = 0, max_s = 0, untimed_cpu_s = 0;
  const double cpu0 = process_cpu_s();
  decltype(make_map()) map;
  for (auto _ : state) {
    const double c0 = process_cpu_s();
    map.reset();
    map = make_map();
    untimed_cpu_s += process_cpu_s() - c0;
    double iteration_s = 0;
    for (int f = 0; f < frames; ++f) {
      const auto t0 = std::chrono::steady_clock::now();
      integrate(*map, q.depth_m[f], q.T_pen_camera[f]);
      const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
      iteration_s += s;
      max_s = std::max(max_s, s);
    }
    state.SetIterationTime(iteration_s);
    total_s += iteration_s;
  }
  const auto n = static_cast<double>(state.iterations()) * frames;
  state.counters["frames"] = frames;
  state.counters["ms_per_frame"] = 1e3 * total_s / n;
  state.counters["max_ms_per_frame"] = 1e3 * max_s;
  state.counters["cpu_ms_per_frame"] = 1e3 * (process_cpu_s() - cpu0 - untimed_cpu_s) / n;
  finish(*map, q, frames);
}

void BM_map_projective(benchmark::State& state) {
  const tbb::global_control threads(tbb::global_control::max_allowed_parallelism, kThreads);
  const mapping::MapConfig config;
  mapping::ProjectiveIntegrator integrator(sequence(static_cast<int>(state.range(0))).camera,
                                           config);
  double surface_leaves = 0, free_leaves = 0;  // leaves updated, over all iterations
  run(
      state, [&] { return std::make_unique<mapping::OccupancyMap>(config); },
      [&](mapping::OccupancyMap& map, const ImageF32& depth, const Eigen::Isometry3d& T) {
        const mapping::IntegrationStats st = integrator.integrate(map, depth, T);
        surface_leaves += static_cast<double>(st.surface_leaves);
        free_leaves += static_cast<double>(st.free_leaves);
      },
      [&](const mapping::OccupancyMap& map, const Sequence& q, int frames) {
        const double n = static_cast<double>(state.iterations()) * frames;
        state.counters["surface_leaves"] = surface_leaves / n;
        state.counters["free_leaves"] = free_leaves / n;
        // Upper bound: every voxel of every leaf the frame updated (surface or free).
        state.counters["voxels_per_frame"] = 512 * (surface_leaves + free_leaves) / n;
        state.counters["memory_MB"] = static_cast<double>(map.memory_bytes()) / 1e6;
        const auto file = std::filesystem::temp_directory_path() / "pensight_mapping_bench.vdb";
        mapping::write_map_vdb(map, file);
        state.counters["vdb_MB"] = static_cast<double>(std::filesystem::file_size(file)) / 1e6;
        std::filesystem::remove(file);
        report_quality(state, map_quality(q, frames, config, [&](const Eigen::Vector3d& p) {
                         return map.log_odds_at(p);
                       }));
      });
}
BENCHMARK(BM_map_projective)
    ->ArgNames({"seq", "frames"})
    ->Args({0, 10})
    ->Args({0, 0})
    ->Args({1, 0})
    ->UseManualTime()
    ->Unit(benchmark::kMillisecond);

// Serial by design; slow, so one iteration of a few frames.
void BM_map_raycast(benchmark::State& state) {
  const mapping::MapConfig config;
  mapping::RaycastIntegrator integrator(sequence(static_cast<int>(state.range(0))).camera, config);
  run(
      state, [&] { return std::make_unique<mapping::OccupancyMap>(config); },
      [&](mapping::OccupancyMap& map, const ImageF32& depth, const Eigen::Isometry3d& T) {
        benchmark::DoNotOptimize(integrator.integrate(map, depth, T));
      },
      [&](const mapping::OccupancyMap& map, const Sequence& q, int frames) {
        state.counters["memory_MB"] = static_cast<double>(map.memory_bytes()) / 1e6;
        report_quality(state, map_quality(q, frames, config, [&](const Eigen::Vector3d& p) {
                         return map.log_odds_at(p);
                       }));
      });
}
BENCHMARK(BM_map_raycast)
    ->ArgNames({"seq", "frames"})
    ->Args({0, 10})
    ->Iterations(1)
    ->UseManualTime()
    ->Unit(benchmark::kMillisecond);

#if PENSIGHT_HAVE_WAVEMAP
// wavemap's own thread pool of 2 (wavemap_peer.cpp).
void BM_map_wavemap(benchmark::State& state) {
  const mapping::MapConfig config;
  const Sequence& seq = sequence(static_cast<int>(state.range(0)));
  const bench::WavemapPeerConfig peer_config{.voxel_m = config.voxel_m,
                                             .min_range_m = config.min_range_m,
                                             .max_range_m = config.max_range_m};
  run(
      state, [&] { return std::make_unique<bench::WavemapPeer>(seq.camera, peer_config); },
      [&](bench::WavemapPeer& peer, const ImageF32& depth, const Eigen::Isometry3d& T) {
        peer.integrate(depth, T);
      },
      [&](const bench::WavemapPeer& peer, const Sequence& q, int frames) {
        state.counters["memory_MB"] = static_cast<double>(peer.memory_bytes()) / 1e6;
        report_quality(state, map_quality(q, frames, config, [&](const Eigen::Vector3d& p) {
                         return peer.log_odds_at(p);
                       }));
      });
}
BENCHMARK(BM_map_wavemap)
    ->ArgNames({"seq", "frames"})
    ->Args({0, 10})
    ->Args({0, 0})
    ->Args({1, 0})
    ->UseManualTime()
    ->Unit(benchmark::kMillisecond);
#endif

}  // namespace
