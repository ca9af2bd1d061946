#include "core/util/progress_bar.h"

#include <unistd.h>

#include <algorithm>
#include <cstdio>

namespace loom {

ProgressBar::ProgressBar(std::string label) : label_(std::move(label)), terminal_(::isatty(STDERR_FILENO) == 1) {}

ProgressBar::~ProgressBar() {
  if (terminal_ && last_permille_ >= 0) std::fputc('\n', stderr);
}

void ProgressBar::Update(double fraction, std::string_view stage) {
  if (!terminal_) return;
  const int permille = static_cast<int>(std::clamp(fraction, 0.0, 1.0) * 1000.0);
  if (permille / 5 == last_permille_ / 5 && stage == last_stage_) return;
  last_permille_ = permille;
  last_stage_ = stage;
  constexpr int kWidth = 30;
  const int filled = permille * kWidth / 1000;
  std::fprintf(stderr, "\r%s [%.*s%*s] %5.1f%% %-40.40s", label_.c_str(), filled,
               "##############################", kWidth - filled, "", permille / 10.0, last_stage_.c_str());
  std::fflush(stderr);
}

}  // namespace loom
