#pragma once
// Sets an environment variable for one test and puts the caller's value back (ctest may run a test
// under the launcher, which sets HSDF_DEVICE; a Vulkan driver reads its own variables, such as
// RADV_FORCE_FAMILY, when an instance is created).
#include <cstdlib>
#include <optional>
#include <string>

namespace hsdftest {

class ScopedEnv {
 public:
  ScopedEnv(const char* name, const char* value) : name_(name) {
    if (const char* old = std::getenv(name)) saved_ = old;
    setenv(name, value, 1);
  }
  ~ScopedEnv() {
    if (saved_)
      setenv(name_, saved_->c_str(), 1);
    else
      unsetenv(name_);
  }
  ScopedEnv(const ScopedEnv&) = delete;
  ScopedEnv& operator=(const ScopedEnv&) = delete;

 private:
  const char* name_;
  std::optional<std::string> saved_;
};

}  // namespace hsdftest
