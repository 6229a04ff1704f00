#pragma once
// Where the tests find their files: the sample assets (samples/assets) and the test data
// (tests/data). Each is the folder an environment variable names when it is set, else the one in
// this source tree: a packed test folder run on another machine (scripts/pack_gpu_tests.sh) has no
// source tree, and sets HSDF_ASSET_DIR and HSDF_TEST_DATA_DIR to its copies.
#include <filesystem>
#include <optional>
#include <string>

namespace hsdftest {

// A file of samples/assets: $HSDF_ASSET_DIR/name, else this source tree's.
std::filesystem::path sampleAsset(const std::string& name);

// A file of tests/data, `relative` to it ("gltf/camera_cube.gltf"): under $HSDF_TEST_DATA_DIR,
// else this source tree's.
std::filesystem::path testData(const std::string& relative);

// An environment variable set for a scope (a test pointing HSDF_SHADER_DIR at broken shaders):
// the destructor puts back the value it had, or unsets it, whichever way the test ends. A packed
// test folder sets HSDF_SHADER_DIR for the whole run, so "unset afterwards" would break the tests
// after it.
class ScopedEnvironment {
 public:
  ScopedEnvironment(std::string name, const std::string& value);
  ~ScopedEnvironment();
  ScopedEnvironment(const ScopedEnvironment&) = delete;
  ScopedEnvironment& operator=(const ScopedEnvironment&) = delete;
  void set(const std::string& value);

 private:
  std::string name_;
  std::optional<std::string> previous_;
};

// A path under the system's temporary folder that no other process uses (the process id and a
// count in its name: two test runs share /tmp on one machine, and a fixed name let one run read
// or delete the other's file), removed with whatever is under it when the scope ends, however the
// test ends. Nothing is created: the test writes the file or folder it needs at path().
class ScopedTempPath {
 public:
  explicit ScopedTempPath(const std::string& name);
  ~ScopedTempPath();
  ScopedTempPath(const ScopedTempPath&) = delete;
  ScopedTempPath& operator=(const ScopedTempPath&) = delete;
  const std::filesystem::path& path() const { return path_; }

 private:
  std::filesystem::path path_;
};

}  // namespace hsdftest
