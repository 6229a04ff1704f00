#include "engine/gpu/pipeline_cache.h"

#include <algorithm>
#include <cstring>
#include <system_error>
#include <utility>
#include <vector>

#include <fmt/format.h>

#include "engine/core/files.h"
#include "engine/core/log.h"
#include "engine/gpu/vk_check.h"

namespace engine::gpu {
namespace {

// A cache file larger than this is not a pipeline cache of this engine's few hundred pipelines.
constexpr std::uint64_t kMaxCacheFileBytes = std::uint64_t(256) << 20;

// The footer after the driver's bytes: a tag, their length and their FNV-1a 64 hash.
constexpr std::array<std::uint8_t, 8> kFooterTag = {'E', 'N', 'G', 'P', 'C', 'A', 'C', '1'};
constexpr std::size_t kFooterBytes = kFooterTag.size() + 2 * sizeof(std::uint64_t);

std::uint32_t readU32(std::span<const std::uint8_t> data, std::size_t offset) {
  std::uint32_t value = 0;
  std::memcpy(&value, data.data() + offset, sizeof(value));
  return value;
}

std::uint64_t readU64(std::span<const std::uint8_t> data, std::size_t offset) {
  std::uint64_t value = 0;
  std::memcpy(&value, data.data() + offset, sizeof(value));
  return value;
}

void appendU64(std::vector<std::uint8_t>& out, std::uint64_t value) {
  std::uint8_t bytes[sizeof(value)];
  std::memcpy(bytes, &value, sizeof(value));
  out.insert(out.end(), std::begin(bytes), std::end(bytes));
}

std::uint64_t fnv1a64(std::span<const std::uint8_t> data) {
  std::uint64_t hash = 0xcbf29ce484222325ull;
  for (const std::uint8_t byte : data) hash = (hash ^ byte) * 0x100000001b3ull;
  return hash;
}

// The file's bytes, or none where there is no file or it cannot be read (logged: the run goes on
// with an empty cache).
std::vector<std::uint8_t> readCacheFile(const std::filesystem::path& file) {
  std::error_code error;
  if (file.empty() || !std::filesystem::exists(file, error)) return {};
  Expected<std::vector<std::uint8_t>> bytes = readBinaryFile(file, kMaxCacheFileBytes);
  if (!bytes) {
    log::warn("pipeline cache '{}' not read ({}); starting with an empty cache", file.string(), bytes.error().message);
    return {};
  }
  return std::move(*bytes);
}

}  // namespace

PipelineCacheIdentity pipelineCacheIdentity(VkPhysicalDevice device) {
  VkPhysicalDeviceProperties properties{};
  vkGetPhysicalDeviceProperties(device, &properties);
  PipelineCacheIdentity identity;
  identity.vendorID = properties.vendorID;
  identity.deviceID = properties.deviceID;
  std::copy(std::begin(properties.pipelineCacheUUID), std::end(properties.pipelineCacheUUID), identity.uuid.begin());
  return identity;
}

std::optional<std::string> pipelineCacheMismatch(std::span<const std::uint8_t> data,
                                                 const PipelineCacheIdentity& identity) {
  // VkPipelineCacheHeaderVersionOne: headerSize, headerVersion, vendorID, deviceID (4 bytes each,
  // little-endian on every platform this engine runs on), then pipelineCacheUUID.
  constexpr std::size_t kHeaderBytes = 16 + VK_UUID_SIZE;
  if (data.size() < kHeaderBytes)
    return fmt::format("{} bytes, shorter than a cache header ({} bytes)", data.size(), kHeaderBytes);
  const std::uint32_t headerSize = readU32(data, 0);
  if (headerSize < kHeaderBytes || headerSize > data.size())
    return fmt::format("a header size of {} bytes (expected at least {}, within the file's {})", headerSize,
                       kHeaderBytes, data.size());
  if (readU32(data, 4) != VK_PIPELINE_CACHE_HEADER_VERSION_ONE)
    return fmt::format("header version {} (this engine reads version 1)", readU32(data, 4));
  if (readU32(data, 8) != identity.vendorID || readU32(data, 12) != identity.deviceID)
    return fmt::format("made for vendor {:#x} device {:#x}, not this device (vendor {:#x} device {:#x})",
                       readU32(data, 8), readU32(data, 12), identity.vendorID, identity.deviceID);
  if (!std::equal(identity.uuid.begin(), identity.uuid.end(), data.begin() + 16))
    return std::string("made by another driver build (pipelineCacheUUID differs)");
  return std::nullopt;
}

std::vector<std::uint8_t> sealPipelineCacheData(std::span<const std::uint8_t> data) {
  std::vector<std::uint8_t> file(data.begin(), data.end());
  file.insert(file.end(), kFooterTag.begin(), kFooterTag.end());
  appendU64(file, data.size());
  appendU64(file, fnv1a64(data));
  return file;
}

Expected<std::span<const std::uint8_t>> unsealPipelineCacheData(std::span<const std::uint8_t> file,
                                                                const PipelineCacheIdentity& identity) {
  if (file.size() < kFooterBytes) return makeError(fmt::format("{} bytes, too short for a cache file", file.size()));
  const std::size_t footer = file.size() - kFooterBytes;
  if (!std::equal(kFooterTag.begin(), kFooterTag.end(), file.begin() + std::ptrdiff_t(footer)))
    return makeError("no cache footer at its end (cut short, or not a cache file of this engine)");
  const std::uint64_t length = readU64(file, footer + kFooterTag.size());
  if (length != footer) return makeError(fmt::format("the footer counts {} bytes, the file holds {}", length, footer));
  const std::span<const std::uint8_t> data = file.first(footer);
  if (readU64(file, footer + kFooterTag.size() + sizeof(std::uint64_t)) != fnv1a64(data))
    return makeError("its checksum does not match (damaged)");
  if (const std::optional<std::string> why = pipelineCacheMismatch(data, identity)) return makeError(*why);
  return data;
}

Expected<PipelineCache> PipelineCache::create(VkDevice device, const PipelineCacheIdentity& identity,
                                              const std::filesystem::path& file) {
  PipelineCache cache;
  cache.device_ = device;
  cache.file_ = file;
  const std::vector<std::uint8_t> bytes = readCacheFile(file);
  std::span<const std::uint8_t> seed;
  if (!bytes.empty()) {
    Expected<std::span<const std::uint8_t>> unsealed = unsealPipelineCacheData(bytes, identity);
    if (unsealed)
      seed = *unsealed;
    else
      log::warn("pipeline cache '{}' ignored: {}; it is replaced when this run saves", file.string(),
                unsealed.error().message);
  }
  VkPipelineCacheCreateInfo info{VK_STRUCTURE_TYPE_PIPELINE_CACHE_CREATE_INFO};
  info.initialDataSize = seed.size();
  info.pInitialData = seed.empty() ? nullptr : seed.data();
  VK_TRY(vkCreatePipelineCache(device, &info, nullptr, &cache.cache_));
  cache.loadedBytes_ = seed.size();
  if (!seed.empty()) log::info("pipeline cache '{}': {} bytes loaded", file.string(), seed.size());
  return cache;
}

Status PipelineCache::save() const {
  if (file_.empty() || !cache_) return {};
  std::size_t size = 0;
  VK_TRY(vkGetPipelineCacheData(device_, cache_, &size, nullptr));
  std::vector<std::uint8_t> data(size);
  VK_TRY(vkGetPipelineCacheData(device_, cache_, &size, data.data()));
  data.resize(size);
  return writeBinaryFile(file_, sealPipelineCacheData(data));
}

PipelineCache::~PipelineCache() { destroy(); }

PipelineCache::PipelineCache(PipelineCache&& other) noexcept { *this = std::move(other); }

PipelineCache& PipelineCache::operator=(PipelineCache&& other) noexcept {
  if (this != &other) {
    destroy();
    device_ = std::exchange(other.device_, VK_NULL_HANDLE);
    cache_ = std::exchange(other.cache_, VK_NULL_HANDLE);
    file_ = std::move(other.file_);
    loadedBytes_ = std::exchange(other.loadedBytes_, 0);
  }
  return *this;
}

void PipelineCache::destroy() noexcept {
  if (cache_) vkDestroyPipelineCache(device_, cache_, nullptr);
  cache_ = VK_NULL_HANDLE;
}

}  // namespace engine::gpu
