#pragma once
// A one-line terminal progress bar on stderr, redrawn in place; silent when stderr is not a
// terminal (logs, CI) except for the final line.
#include <cstddef>
#include <string>

#include "core/timing.h"

namespace pensight::app {

class ProgressBar {
 public:
  explicit ProgressBar(std::string label);
  void update(size_t done, size_t total);

 private:
  std::string label_;
  bool tty_ = false;
  Stopwatch clock_;
  int last_percent_ = -1;
};

}  // namespace pensight::app
