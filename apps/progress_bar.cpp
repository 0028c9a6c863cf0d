#include "apps/progress_bar.h"

#include <unistd.h>

#include <cstdio>

namespace pensight::app {

ProgressBar::ProgressBar(std::string label) : label_(std::move(label)), tty_(isatty(2)) {}

void ProgressBar::update(size_t done, size_t total) {
  const int percent = total ? static_cast<int>(100 * done / total) : 100;
  const bool last = done >= total;
  if (percent == last_percent_ && !last) return;
  last_percent_ = percent;
  if (!tty_ && !last) return;
  constexpr int kWidth = 30;
  const int filled = kWidth * percent / 100;
  const double seconds = clock_.elapsed_ms() / 1000;
  std::fprintf(stderr, "\r%s [%.*s%*s] %3d%% %zu/%zu %.1f s%s", label_.c_str(), filled,
               "##############################", kWidth - filled, "", percent, done, total, seconds,
               last ? "\n" : "");
  std::fflush(stderr);
}

}  // namespace pensight::app
