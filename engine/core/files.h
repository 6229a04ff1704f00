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
Status writeBinaryFile(const std::filesystem::path& path, std::span<const std::uint8_t> bytes);
Status writeTextFile(const std::filesystem::path& path, std::string_view text);

}  // namespace engine
