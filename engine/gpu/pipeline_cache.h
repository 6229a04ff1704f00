#pragma once
// The driver's pipeline cache, optionally kept in a file across runs. A pipeline compiled by an
// earlier run is then found by its description and costs a look-up, not a compile (on lavapipe and
// on desktop drivers a compile takes tens to hundreds of milliseconds). The file holds the driver's
// bytes (vkGetPipelineCacheData) followed by a footer of this engine (a tag, their length and a
// checksum): a file cut short or damaged anywhere is refused before the driver sees it, and one
// from another device, driver or version is refused by the driver's header
// (VkPipelineCacheHeaderVersionOne), which drivers are not all trusted to check.
#include <array>
#include <cstdint>
#include <filesystem>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include <vulkan/vulkan.h>

#include "engine/core/expected.h"

namespace engine::gpu {

// What a cache's header must name for this device's driver to accept it.
struct PipelineCacheIdentity {
  std::uint32_t vendorID = 0;
  std::uint32_t deviceID = 0;
  std::array<std::uint8_t, VK_UUID_SIZE> uuid{};
};
PipelineCacheIdentity pipelineCacheIdentity(VkPhysicalDevice device);

// Why the driver's bytes `data` cannot seed a cache for `identity` (too short for its header, a
// header of another size or version, another vendor, device or driver build), or nothing when
// they can.
std::optional<std::string> pipelineCacheMismatch(std::span<const std::uint8_t> data,
                                                 const PipelineCacheIdentity& identity);
// A cache file's bytes: the driver's `data` and the footer.
std::vector<std::uint8_t> sealPipelineCacheData(std::span<const std::uint8_t> data);
// The driver's bytes in a cache file's `file` bytes, or an error saying why the file is unusable
// (no footer, a length or checksum that does not match, a mismatched header).
Expected<std::span<const std::uint8_t>> unsealPipelineCacheData(std::span<const std::uint8_t> file,
                                                                const PipelineCacheIdentity& identity);

// A VkPipelineCache, internally synchronized (created without EXTERNALLY_SYNCHRONIZED): pipelines
// may be compiled through it from several threads at once.
class PipelineCache {
 public:
  PipelineCache() = default;
  // Seeded from `file` when it is given, exists and its header matches `identity`; a missing file
  // starts empty, and an unusable one is logged (with the reason) and ignored, never an error.
  static Expected<PipelineCache> create(VkDevice device, const PipelineCacheIdentity& identity,
                                        const std::filesystem::path& file);
  ~PipelineCache();
  PipelineCache(PipelineCache&& other) noexcept;
  PipelineCache& operator=(PipelineCache&& other) noexcept;
  PipelineCache(const PipelineCache&) = delete;
  PipelineCache& operator=(const PipelineCache&) = delete;

  VkPipelineCache handle() const { return cache_; }
  // The bytes the cache was seeded with (0: it started empty).
  std::size_t loadedBytes() const { return loadedBytes_; }
  const std::filesystem::path& file() const { return file_; }
  // Writes the cache's data to file() (replacing it whole: a temporary file renamed over it);
  // nothing to do without a file.
  Status save() const;

 private:
  void destroy() noexcept;
  VkDevice device_ = VK_NULL_HANDLE;
  VkPipelineCache cache_ = VK_NULL_HANDLE;
  std::filesystem::path file_;
  std::size_t loadedBytes_ = 0;
};

}  // namespace engine::gpu
