#pragma once
// CPU seconds of the whole process (every thread, lavapipe's and TBB's included): on a shared
// machine this moves far less with the load than wall time does.
#include <ctime>

#include "core/units.h"

namespace pensight::bench {

inline double process_cpu_s() {
  timespec t{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
  return static_cast<double>(t.tv_sec) + ns_to_seconds(t.tv_nsec);
}

}  // namespace pensight::bench
