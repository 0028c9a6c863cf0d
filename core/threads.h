#pragma once
// The one rule for a worker-thread setting: a positive count is taken as given, 0 (or less) means
// one thread per hardware thread, and never fewer than one.
#include <algorithm>
#include <thread>

namespace pensight {

inline int worker_threads(int requested) {
  if (requested > 0) return requested;
  return static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
}

}  // namespace pensight
