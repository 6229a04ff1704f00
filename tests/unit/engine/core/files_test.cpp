// Whole-file writes (engine/core/files.h, image_io.h): what a full disk or an interrupted write
// leaves behind, and what the error says.
#include <gtest/gtest.h>

#include <csignal>
#include <filesystem>
#include <string>
#include <vector>

#include <sys/resource.h>

#include "engine/core/files.h"
#include "engine/core/image_io.h"

namespace engine {
namespace {

std::filesystem::path freshFolder(const std::string& name) {
  const std::filesystem::path folder = std::filesystem::temp_directory_path() / ("hsdf_files_test_" + name);
  std::filesystem::remove_all(folder);
  std::filesystem::create_directories(folder);
  return folder;
}

std::size_t entries(const std::filesystem::path& folder) {
  std::size_t n = 0;
  for ([[maybe_unused]] const auto& entry : std::filesystem::directory_iterator(folder)) ++n;
  return n;
}

// Files past this size cannot be written by this process (EFBIG; SIGXFSZ ignored), as if the disk
// were full after the first bytes: root ignores a read-only folder, but not this limit.
class FileSizeLimit {
 public:
  explicit FileSizeLimit(rlim_t bytes) {
    previousHandler_ = std::signal(SIGXFSZ, SIG_IGN);
    getrlimit(RLIMIT_FSIZE, &previous_);
    rlimit limit = previous_;
    limit.rlim_cur = bytes;
    setrlimit(RLIMIT_FSIZE, &limit);
  }
  ~FileSizeLimit() {
    setrlimit(RLIMIT_FSIZE, &previous_);
    std::signal(SIGXFSZ, previousHandler_);
  }

 private:
  rlimit previous_{};
  void (*previousHandler_)(int) = nullptr;
};

// Tricky: the write fails after some bytes went to disk (a full disk); the old file must stay whole
// (it was truncated first: a killed or failed bake destroyed the previous .hsdf), no temporary file
// may be left beside it, and the error must name the file and the reason.
TEST(Files, AFailedWriteLeavesThePreviousFileWhole) {
  const std::filesystem::path folder = freshFolder("failed");
  const std::filesystem::path path = folder / "result.bin";
  ASSERT_TRUE(writeTextFile(path, "previous contents").ok());
  const std::vector<std::uint8_t> large(1 << 20, 0x5a);
  Status written;
  {
    const FileSizeLimit limit(4096);
    written = writeBinaryFile(path, large);
  }
  ASSERT_FALSE(written.ok()) << "1 MiB written under a 4 KiB file size limit";
  EXPECT_NE(written.error().message.find(path.string() + ": write failed: "), std::string::npos)
      << written.error().message;
  auto kept = readTextFile(path);
  ASSERT_TRUE(kept.ok());
  EXPECT_EQ(*kept, "previous contents");
  EXPECT_EQ(entries(folder), 1u) << "a temporary file was left behind";
  ASSERT_TRUE(writeBinaryFile(path, large).ok());
  EXPECT_EQ(std::filesystem::file_size(path), large.size());
  std::filesystem::remove_all(folder);
}

// Tricky: a small write sits in the stream's buffer until the close, where a full disk shows (a
// settings file of 760 bytes written to /dev/full reported success); a device is written in place
// (renaming a file over /dev/full would replace the device). PNGs go the same way (stb's writer
// checked nothing: a truncated screenshot behind "screenshot: ..." and exit 0).
TEST(Files, AFullDiskIsAnErrorEvenForSmallWrites) {
  if (!std::filesystem::is_character_file("/dev/full")) GTEST_SKIP() << "no /dev/full";
  const Status text = writeTextFile("/dev/full", "{\"method\": \"cells\"}\n");
  ASSERT_FALSE(text.ok());
  EXPECT_NE(text.error().message.find("/dev/full: write failed: No space left on device"), std::string::npos)
      << text.error().message;
  EXPECT_TRUE(std::filesystem::is_character_file("/dev/full"));
  const std::vector<std::uint8_t> pixels(4 * 4 * 4, 200);
  const Status png = writePng("/dev/full", pixels, 4, 4, 4);
  ASSERT_FALSE(png.ok());
  EXPECT_NE(png.error().message.find("No space left on device"), std::string::npos) << png.error().message;
}

// Tricky: the check runs before a long bake, so it must find what the write would (a folder where a
// file is asked for, a file where a folder is needed) and leave nothing behind when it passes.
TEST(Files, CheckWritableFindsWhatTheWriteWould) {
  const std::filesystem::path folder = freshFolder("check");
  ASSERT_TRUE(writeTextFile(folder / "plain", "x").ok());
  EXPECT_TRUE(checkWritable(folder / "new" / "out.hsdf").ok());
  EXPECT_TRUE(std::filesystem::is_directory(folder / "new")) << "its folder is made, as the write makes it";
  EXPECT_EQ(entries(folder / "new"), 0u);
  const Status underFile = checkWritable(folder / "plain" / "out.hsdf");
  ASSERT_FALSE(underFile.ok());
  EXPECT_NE(underFile.error().message.find("out.hsdf"), std::string::npos) << underFile.error().message;
  const Status aFolder = checkWritable(folder / "new");
  ASSERT_FALSE(aFolder.ok());
  EXPECT_NE(aFolder.error().message.find("is a directory"), std::string::npos) << aFolder.error().message;
  std::filesystem::remove_all(folder);
}

}  // namespace
}  // namespace engine
