// Where the tests find their files (test_files.h): a packed test folder on a GPU machine has no
// source tree and points the tests at its copies through the environment, and a test that points
// HSDF_SHADER_DIR elsewhere must leave the run's value behind, so each case is pinned here.
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <string>

#include "test_files.h"

namespace {

std::string environment(const char* name) {
  const char* value = std::getenv(name);
  return value ? value : "<unset>";
}

// Tricky: unset and empty both mean the source tree; the files the tests read must be there.
TEST(TestFiles, WithoutTheVariablesTheSourceTreesFiles) {
  hsdftest::ScopedEnvironment assets("HSDF_ASSET_DIR", "");
  hsdftest::ScopedEnvironment data("HSDF_TEST_DATA_DIR", "");
  EXPECT_TRUE(std::filesystem::is_regular_file(hsdftest::sampleAsset("bunny.glb")));
  EXPECT_TRUE(std::filesystem::is_regular_file(hsdftest::testData("gltf/camera_cube.gltf")));
}

TEST(TestFiles, TheVariablesNameThePackedCopies) {
  hsdftest::ScopedEnvironment assets("HSDF_ASSET_DIR", "/pack/assets");
  hsdftest::ScopedEnvironment data("HSDF_TEST_DATA_DIR", "/pack/data");
  EXPECT_EQ(hsdftest::sampleAsset("bunny.glb"), std::filesystem::path("/pack/assets/bunny.glb"));
  EXPECT_EQ(hsdftest::testData("gltf/camera_cube.gltf"), std::filesystem::path("/pack/data/gltf/camera_cube.gltf"));
}

// Tricky: the value the run set must come back (unsetting it broke every later test of a packed
// run), and a variable that was unset must be unset again, whichever set() came last.
TEST(TestFiles, ScopedEnvironmentPutsBackWhatWasThere) {
  const std::string name = "HSDF_TEST_FILES_TEST_VARIABLE";
  unsetenv(name.c_str());
  {
    hsdftest::ScopedEnvironment outer(name, "run");
    {
      hsdftest::ScopedEnvironment inner(name, "first");
      inner.set("second");
      EXPECT_EQ(environment(name.c_str()), "second");
    }
    EXPECT_EQ(environment(name.c_str()), "run");
  }
  EXPECT_EQ(environment(name.c_str()), "<unset>");
}

}  // namespace
