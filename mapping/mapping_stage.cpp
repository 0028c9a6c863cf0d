#include "mapping/mapping_stage.h"

#include <chrono>

#include "core/error.h"
#include "core/log.h"

namespace pensight::mapping {

MappingStage::MappingStage(const PinholeCamera& camera, const MapConfig& config,
                           size_t queue_frames)
    : map_(config), integrator_(camera, config), queue_(queue_frames, QueuePolicy::kDropOldest) {
  worker_ = std::thread([this] { loop(); });
}

MappingStage::~MappingStage() {
  finish();
}

void MappingStage::push(const FrameResult& result) {
  // A depth sensor's image (or replayed truth) when the frame carries one, else the network's.
  push(result.timestamp_ns, result.depth_m ? result.depth_m : result.dense_depth_m,
       result.global_pose.T_pen_camera);
}

void MappingStage::push(int64_t t_ns, std::shared_ptr<const ImageF32> depth_m,
                        const Eigen::Isometry3d& T_pen_camera) {
  {
    std::lock_guard lock(state_mutex_);
    if (finished_) throw Error("MappingStage: frame pushed after finish(); push before finishing");
    if (!depth_m) {
      ++counters_.without_depth;
      return;
    }
    if (!T_pen_camera.matrix().allFinite()) {
      ++counters_.without_pose;
      return;
    }
  }
  queue_.push({t_ns, std::move(depth_m), T_pen_camera, StageMeter::Clock::now()});
}

void MappingStage::loop() {
  while (auto item = queue_.pop()) {
    const auto t0 = StageMeter::Clock::now();
    try {
      std::lock_guard lock(map_mutex_);
      integrator_.integrate(map_, *item->depth_m, item->T_pen_camera);
    } catch (const std::exception& e) {
      log_warning("mapping: frame at " + std::to_string(item->t_ns) + " ns skipped: " + e.what());
      continue;
    }
    const double ms =
        std::chrono::duration<double, std::milli>(StageMeter::Clock::now() - t0).count();
    std::lock_guard lock(state_mutex_);
    ++counters_.integrated;
    meter_.add(ms, item->pushed);
  }
}

void MappingStage::finish() {
  {
    std::lock_guard lock(state_mutex_);
    if (finished_) return;
    finished_ = true;
  }
  queue_.close();
  worker_.join();
  std::lock_guard lock(state_mutex_);
  joined_ = true;
}

void MappingStage::read(const std::function<void(const OccupancyMap&)>& read) const {
  std::lock_guard lock(map_mutex_);
  read(map_);
}

const OccupancyMap& MappingStage::map() const {
  std::lock_guard lock(state_mutex_);
  if (!joined_) {
    throw Error("MappingStage: map() before finish(); use read() while the stage runs");
  }
  return map_;
}

MappingCounters MappingStage::counters() const {
  std::lock_guard lock(state_mutex_);
  MappingCounters c = counters_;
  c.dropped = queue_.dropped();
  return c;
}

StageStats MappingStage::stats() const {
  std::lock_guard lock(state_mutex_);
  return meter_.stats(queue_.dropped());
}

}  // namespace pensight::mapping
