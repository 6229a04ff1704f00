#pragma once
// The log messages of one level written during a scope: a test that checks a warning is said once,
// or an error names the object. The destructor puts the default sink back however the test ends;
// a capture written by hand inside a test body did not when a failed ASSERT returned early, and
// left the log writing into a vector that no longer existed.
#include <cstddef>
#include <mutex>
#include <string>
#include <string_view>
#include <vector>

#include "engine/core/log.h"

namespace hsdftest {

class LogCapture {
 public:
  explicit LogCapture(engine::log::Level level = engine::log::Level::Warning);
  ~LogCapture();
  LogCapture(const LogCapture&) = delete;
  LogCapture& operator=(const LogCapture&) = delete;

  // The messages of the level so far, oldest first (a copy: workers may still be logging).
  std::vector<std::string> messages() const;
  // How many of them contain `text`.
  std::size_t count(std::string_view text) const;

 private:
  mutable std::mutex mutex_;
  std::vector<std::string> messages_;
};

}  // namespace hsdftest
