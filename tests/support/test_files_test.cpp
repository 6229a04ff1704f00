// Where the tests find their files (test_files.h): a packed test folder on a GPU machine has no
// source tree and points the tests at its copies through the environment, and a test that points
// HSDF_SHADER_DIR elsewhere must leave the run's value behind, so each case is pinned here.
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
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

// Tricky: two paths asked for by the same name (two tests, or two runs of one) must differ, the
// name must be kept (an extension decides how a file is read), and the path must be gone after the
// scope with what the test wrote under it, a folder included.
TEST(TestFiles, ScopedTempPathIsUniqueAndRemoved) {
  std::filesystem::path first, second;
  {
    const hsdftest::ScopedTempPath a("same.hsdf"), b("same.hsdf");
    first = a.path();
    second = b.path();
    EXPECT_NE(first, second);
    EXPECT_EQ(first.extension(), ".hsdf");
    EXPECT_EQ(first.parent_path(), std::filesystem::temp_directory_path());
    EXPECT_FALSE(std::filesystem::exists(first)) << "nothing is made before the test writes it";
    std::ofstream(first) << "a file";
    std::filesystem::create_directories(second / "inner");
    std::ofstream(second / "inner" / "x.txt") << "a folder";
    ASSERT_TRUE(std::filesystem::is_regular_file(first));
  }
  EXPECT_FALSE(std::filesystem::exists(first));
  EXPECT_FALSE(std::filesystem::exists(second));
}

}  // namespace
