#include "runtime/timing.h"

#include <algorithm>
#include <cstdio>

namespace pensight {

void StageTimes::add(const std::string& name, double ms) {
  auto it =
      std::find_if(stages_.begin(), stages_.end(), [&](const Stage& s) { return s.name == name; });
  if (it == stages_.end()) it = stages_.insert(stages_.end(), Stage{name, 0.0, 0});
  it->total_ms += ms;
  ++it->count;
}

std::string StageTimes::summary() const {
  std::string out;
  char line[256];
  for (const Stage& s : stages_) {
    const double mean = s.count ? s.total_ms / static_cast<double>(s.count) : 0.0;
    std::snprintf(line, sizeof(line), "  %-28s %6ld x %9.3f ms = %10.1f ms\n", s.name.c_str(),
                  s.count, mean, s.total_ms);
    out += line;
  }
  return out;
}

}  // namespace pensight
