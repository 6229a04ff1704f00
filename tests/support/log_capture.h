#pragma once
// The log messages of one level written during a scope: a test that checks a warning is said once,
// or an error names the object. The destructor puts the default sink back however the test ends;
// a capture written by hand inside a test body did not when a failed ASSERT returned early, and
// left the log writing into a vector that no longer existed.
#include <algorithm>
#include <cstddef>
#include <mutex>
#include <string>
#include <string_view>
#include <vector>

#include "engine/core/log.h"

namespace hsdftest {

// Header-only: a helper of the tests, not a test of its own (log_capture_test.cpp checks it).
class LogCapture {
 public:
  explicit LogCapture(engine::log::Level level = engine::log::Level::Warning) {
    engine::log::setSink([this, level](engine::log::Level written, std::string_view message) {
      if (written != level) return;
      std::lock_guard lock(mutex_);
      messages_.emplace_back(message);
    });
  }
  ~LogCapture() { engine::log::setSink({}); }
  LogCapture(const LogCapture&) = delete;
  LogCapture& operator=(const LogCapture&) = delete;

  // The messages of the level so far, oldest first (a copy: workers may still be logging).
  std::vector<std::string> messages() const {
    std::lock_guard lock(mutex_);
    return messages_;
  }
  // How many of them contain `text`.
  std::size_t count(std::string_view text) const {
    std::lock_guard lock(mutex_);
    return std::size_t(std::count_if(messages_.begin(), messages_.end(),
                                     [&](const std::string& m) { return m.find(text) != std::string::npos; }));
  }

 private:
  mutable std::mutex mutex_;
  std::vector<std::string> messages_;
};

}  // namespace hsdftest
