#include "test_files.h"

#include <unistd.h>

#include <atomic>
#include <cstdint>
#include <cstdlib>
#include <system_error>
#include <utility>

namespace hsdftest {
namespace {

std::filesystem::path underVariable(const char* variable, const char* sourceTree, const std::string& relative) {
  if (const char* dir = std::getenv(variable); dir && *dir) return std::filesystem::path(dir) / relative;
  return std::filesystem::path(sourceTree) / relative;
}

}  // namespace

std::filesystem::path sampleAsset(const std::string& name) { return underVariable("HSDF_ASSET_DIR", HSDF_ASSET_DIR, name); }

std::filesystem::path testData(const std::string& relative) {
  return underVariable("HSDF_TEST_DATA_DIR", HSDF_TEST_DATA_DIR, relative);
}

ScopedEnvironment::ScopedEnvironment(std::string name, const std::string& value) : name_(std::move(name)) {
  if (const char* was = std::getenv(name_.c_str())) previous_ = was;
  set(value);
}

ScopedEnvironment::~ScopedEnvironment() {
  if (previous_) setenv(name_.c_str(), previous_->c_str(), 1);
  else unsetenv(name_.c_str());
}

void ScopedEnvironment::set(const std::string& value) { setenv(name_.c_str(), value.c_str(), 1); }

ScopedTempPath::ScopedTempPath(const std::string& name) {
  static std::atomic<std::uint64_t> count{0};
  path_ = std::filesystem::temp_directory_path() /
          ("hsdf_" + std::to_string(::getpid()) + "_" + std::to_string(count++) + "_" + name);
}

ScopedTempPath::~ScopedTempPath() {
  std::error_code ignored;  // a destructor cannot fail; a file left behind harms no other run
  std::filesystem::remove_all(path_, ignored);
}

}  // namespace hsdftest
