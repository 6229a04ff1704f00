#pragma once
// Whole-file reads and writes with errors that name the file.
#include <cstdint>
#include <filesystem>
#include <span>
#include <string>
#include <vector>

#include "engine/core/expected.h"

namespace engine {

Expected<std::vector<std::uint8_t>> readBinaryFile(const std::filesystem::path& path,
                                                   std::uint64_t maxBytes = std::uint64_t(1) << 32);
Expected<std::string> readTextFile(const std::filesystem::path& path);
// Whole-file writes (their folders made): through a file beside `path` renamed over it, so a write
// that fails or is interrupted leaves the previous file whole; every error (open, write, flush,
// close: a full disk) names the file and its reason. A path that exists and is not a regular file
// (a device, a link) is written in place.
Status writeBinaryFile(const std::filesystem::path& path, std::span<const std::uint8_t> bytes);
Status writeTextFile(const std::filesystem::path& path, std::string_view text);
// Whether `path` can be written (its folder made, a file created there and removed), checked before
// a long job whose result goes there.
Status checkWritable(const std::filesystem::path& path);

}  // namespace engine
