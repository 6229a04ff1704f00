#include "log_capture.h"

#include <algorithm>

namespace hsdftest {

LogCapture::LogCapture(engine::log::Level level) {
  engine::log::setSink([this, level](engine::log::Level written, std::string_view message) {
    if (written != level) return;
    std::lock_guard lock(mutex_);
    messages_.emplace_back(message);
  });
}

LogCapture::~LogCapture() { engine::log::setSink({}); }

std::vector<std::string> LogCapture::messages() const {
  std::lock_guard lock(mutex_);
  return messages_;
}

std::size_t LogCapture::count(std::string_view text) const {
  std::lock_guard lock(mutex_);
  return std::size_t(std::count_if(messages_.begin(), messages_.end(),
                                   [&](const std::string& m) { return m.find(text) != std::string::npos; }));
}

}  // namespace hsdftest
