#include "engine/core/files.h"

#include <atomic>
#include <cerrno>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <fstream>

namespace engine {
namespace {

Error fileError(const std::filesystem::path& path, const std::string& what) {
  return makeError(path.string() + ": " + what);
}

}  // namespace

Expected<std::vector<std::uint8_t>> readBinaryFile(const std::filesystem::path& path,
                                                   std::uint64_t maxBytes) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec)) return fileError(path, "not a readable file");
  const std::uint64_t size = std::filesystem::file_size(path, ec);
  if (ec) return fileError(path, "cannot get size: " + ec.message());
  if (size > maxBytes)
    return fileError(path, "file is " + std::to_string(size) + " bytes, more than the limit of " +
                               std::to_string(maxBytes));
  std::ifstream in(path, std::ios::binary);
  if (!in) return fileError(path, std::string("cannot open: ") + std::strerror(errno));
  std::vector<std::uint8_t> bytes(size);
  if (size > 0 && !in.read(reinterpret_cast<char*>(bytes.data()), static_cast<std::streamsize>(size)))
    return fileError(path, "read failed");
  return bytes;
}

Expected<std::string> readTextFile(const std::filesystem::path& path) {
  auto bytes = readBinaryFile(path);
  if (!bytes) return bytes.error();
  return std::string(bytes->begin(), bytes->end());
}

namespace {

// A file beside `path`, in the same folder (so that renaming it over `path` is atomic), named after
// it and unique within this process.
std::filesystem::path siblingTempPath(const std::filesystem::path& path) {
  static std::atomic<std::uint64_t> counter{0};
  const auto ticks = std::chrono::steady_clock::now().time_since_epoch().count();
  std::string name = ".";  // appended piece by piece: GCC 12 warns falsely (-Wrestrict) on "." + string
  name += path.filename().string();
  name += '.';
  name += std::to_string(ticks);
  name += '-';
  name += std::to_string(counter.fetch_add(1));
  name += ".tmp";
  return path.parent_path() / name;
}

// Writes every byte to `path` and closes it, each step checked: a full disk often shows only at the
// flush or the close, and a stream that is never flushed loses that error in its destructor. Errors
// name `named` (the file the caller asked for).
Status writeAll(const std::filesystem::path& path, std::span<const std::uint8_t> bytes,
                const std::filesystem::path& named) {
  std::FILE* file = std::fopen(path.string().c_str(), "wb");
  if (!file) return fileError(named, std::string("cannot open for writing: ") + std::strerror(errno));
  const std::size_t written = bytes.empty() ? 0 : std::fwrite(bytes.data(), 1, bytes.size(), file);
  const int writeErrno = errno;
  if (written != bytes.size()) {
    std::fclose(file);
    return fileError(named, std::string("write failed: ") + std::strerror(writeErrno));
  }
  if (std::fflush(file) != 0) {
    const int flushErrno = errno;
    std::fclose(file);
    return fileError(named, std::string("write failed: ") + std::strerror(flushErrno));
  }
  if (std::fclose(file) != 0) return fileError(named, std::string("write failed: ") + std::strerror(errno));
  return {};
}

// An existing path that is not a regular file (a device such as /dev/full, a link) is written in
// place, so that it stays what it is; anything else goes through a file beside it.
bool writtenInPlace(const std::filesystem::path& path) {
  std::error_code ec;
  const std::filesystem::file_status status = std::filesystem::symlink_status(path, ec);
  return !ec && std::filesystem::exists(status) && !std::filesystem::is_regular_file(status);
}

void makeParentFolders(const std::filesystem::path& path) {
  if (!path.has_parent_path()) return;
  std::error_code ec;
  std::filesystem::create_directories(path.parent_path(), ec);  // a failure shows when the file is opened
}

}  // namespace

// Written to a file beside `path` and renamed over it: a write that fails or is interrupted (a full
// disk, a signal) leaves the previous file whole, and never a truncated one that looks written.
Status writeBinaryFile(const std::filesystem::path& path, std::span<const std::uint8_t> bytes) {
  makeParentFolders(path);
  if (writtenInPlace(path)) return writeAll(path, bytes, path);
  const std::filesystem::path temp = siblingTempPath(path);
  std::error_code ec;
  if (Status written = writeAll(temp, bytes, path); !written) {
    std::filesystem::remove(temp, ec);
    return written;
  }
  std::filesystem::rename(temp, path, ec);
  if (ec) {
    std::filesystem::remove(temp, ec);
    return fileError(path, "cannot replace it: " + ec.message());
  }
  return {};
}

Status checkWritable(const std::filesystem::path& path) {
  makeParentFolders(path);
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec)) return fileError(path, "is a directory, not a file");
  if (writtenInPlace(path)) {
    std::FILE* file = std::fopen(path.string().c_str(), "ab");
    if (!file) return fileError(path, std::string("cannot open for writing: ") + std::strerror(errno));
    std::fclose(file);
    return {};
  }
  const std::filesystem::path temp = siblingTempPath(path);
  std::FILE* file = std::fopen(temp.string().c_str(), "wb");
  if (!file) return fileError(path, std::string("cannot create a file there: ") + std::strerror(errno));
  std::fclose(file);
  std::filesystem::remove(temp, ec);
  return {};
}

Status writeTextFile(const std::filesystem::path& path, std::string_view text) {
  return writeBinaryFile(path, std::span(reinterpret_cast<const std::uint8_t*>(text.data()), text.size()));
}

}  // namespace engine
