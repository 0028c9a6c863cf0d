#pragma once
// The mapping stage of the vehicle runtime: a worker thread that integrates each frame's depth at
// its camera pose (FrameResult::depth_m at global_pose.T_pen_camera) into the occupancy map.
// push() never waits for it: frames queue in a drop-oldest queue (2 deep by default), so a slow
// map costs map updates, never pose latency. Frames without depth or without a finite camera
// pose are counted and not queued.
#include <Eigen/Geometry>

#include <functional>
#include <memory>
#include <mutex>
#include <thread>

#include "mapping/occupancy_map.h"
#include "mapping/projective_integrator.h"
#include "pipeline/bounded_queue.h"
#include "pipeline/pipeline.h"
#include "pipeline/stage_stats.h"

namespace pensight::mapping {

struct MappingCounters {
  size_t integrated = 0;
  size_t dropped = 0;        // replaced in the queue by a newer frame
  size_t without_depth = 0;  // the frame carried no depth image
  size_t without_pose = 0;   // T_pen_camera not finite (before the global pose locks, ...)
};

class MappingStage {
 public:
  // Throws pensight::Error like ProjectiveIntegrator for a bad camera or config.
  MappingStage(const PinholeCamera& camera, const MapConfig& config, size_t queue_frames = 2);
  // finish(), then joins the worker.
  ~MappingStage();
  MappingStage(const MappingStage&) = delete;
  MappingStage& operator=(const MappingStage&) = delete;

  // Thread-safe, never blocks on the integration. Throws pensight::Error after finish().
  void push(const FrameResult& result);
  void push(int64_t t_ns, std::shared_ptr<const ImageF32> depth_m,
            const Eigen::Isometry3d& T_pen_camera);

  // Integrates what is queued and stops the worker. Idempotent.
  void finish();

  // Runs `read` on the map with integration paused (e.g. a distance query while running).
  void read(const std::function<void(const OccupancyMap&)>& read) const;
  // The map after finish(); throws pensight::Error before.
  const OccupancyMap& map() const;

  MappingCounters counters() const;
  // "map" (the published wavemap node's row of the timing table): integration time per frame;
  // latency from push() to the frame's integration.
  StageStats stats() const;

 private:
  struct Item {
    int64_t t_ns = 0;
    std::shared_ptr<const ImageF32> depth_m;
    Eigen::Isometry3d T_pen_camera;
    StageMeter::Clock::time_point pushed;
  };
  void loop();

  OccupancyMap map_;
  ProjectiveIntegrator integrator_;
  BoundedQueue<Item> queue_;
  mutable std::mutex map_mutex_;    // integration vs read()
  mutable std::mutex state_mutex_;  // counters, meter, finished
  MappingCounters counters_;
  StageMeter meter_{"map"};
  bool finished_ = false;
  bool joined_ = false;
  std::thread worker_;
};

}  // namespace pensight::mapping
