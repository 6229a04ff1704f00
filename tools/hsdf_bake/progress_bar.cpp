#include "progress_bar.h"

#include <algorithm>
#include <cmath>

namespace hsdf::tools {
namespace {
constexpr int kWidth = 32;
}

bool ProgressBar::update(float fraction) {
  const int percent = std::clamp(int(std::floor(fraction * 100.0f)), 0, 100);
  if (percent != shown_) draw(percent);
  return true;
}

void ProgressBar::finish() {
  if (shown_ != 100) draw(100);
  std::fputc('\n', out_);
  std::fflush(out_);
}

void ProgressBar::draw(int percent) {
  shown_ = percent;
  const int filled = percent * kWidth / 100;
  std::fprintf(out_, "\r%s [%s%s] %3d%%", label_.c_str(), std::string(std::size_t(filled), '#').c_str(),
               std::string(std::size_t(kWidth - filled), '-').c_str(), percent);
  std::fflush(out_);
}

}  // namespace hsdf::tools
