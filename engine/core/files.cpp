#include "engine/core/files.h"

#include <cerrno>
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

Status writeBinaryFile(const std::filesystem::path& path, std::span<const std::uint8_t> bytes) {
  if (path.has_parent_path()) {
    std::error_code ec;
    std::filesystem::create_directories(path.parent_path(), ec);
  }
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  if (!out) return fileError(path, std::string("cannot open for writing: ") + std::strerror(errno));
  out.write(reinterpret_cast<const char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
  if (!out) return fileError(path, "write failed");
  return {};
}

Status writeTextFile(const std::filesystem::path& path, std::string_view text) {
  return writeBinaryFile(path, std::span(reinterpret_cast<const std::uint8_t*>(text.data()), text.size()));
}

}  // namespace engine
