#pragma once
// The Vulkan context: instance, validation messenger, physical device choice (a real GPU when
// present, else Mesa's lavapipe), logical device with Vulkan 1.3 core features, one graphics queue,
// the memory allocator and a command pool for one-off uploads.
#include <atomic>
#include <cstdint>
#include <filesystem>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include <vulkan/vulkan.h>

#include "engine/core/expected.h"
#include "engine/gpu/memory.h"
#include "engine/gpu/pipeline_cache.h"
#include "engine/gpu/shader_statistics.h"

namespace engine::gpu {

enum class DevicePreference {
  Auto,      // env HSDF_DEVICE=gpu|lavapipe|auto if set, else discrete GPU, integrated, anything (lavapipe last)
  Hardware,  // fail when no hardware GPU exists (HSDF_DEVICE is not consulted)
  Software,  // Mesa lavapipe (CPU); what CI uses (HSDF_DEVICE is not consulted)
};

struct ContextDesc {
  // Given to the driver (VkApplicationInfo), which may key per-application settings on them: the
  // program names itself and the engine it ships.
  std::string applicationName = "engine";
  std::string engineName = "engine";
  DevicePreference device = DevicePreference::Auto;
  // Validation layers. Default: on in debug builds, or when HSDF_VALIDATION=1.
  bool validation = defaultValidation();
  // Adds synchronization validation (slower); also switched on by HSDF_SYNC_VALIDATION=1.
  bool synchronizationValidation = false;
  // Extra instance extensions, e.g. those GLFW needs for a surface. Presence turns on the swapchain.
  std::vector<std::string> instanceExtensions;
  bool swapchain = false;
  // The shader compiler's statistics of every pipeline (engine/gpu/shader_statistics.h); off by
  // default. A target that is not there (a device without the extension, no device of the name)
  // fails Context::create naming it.
  ShaderStatisticsDesc shaderStatistics;
  // A file the pipeline cache is seeded from (when it is there and made by this device and driver)
  // and saved to when the context is destroyed; empty: the cache lives as long as the context.
  std::filesystem::path pipelineCacheFile;

  static bool defaultValidation();
};

// Optional capabilities, detected at device creation. Features the engine requires
// (engine/gpu/device_features.h) are not listed: a device without them is rejected.
struct DeviceCapabilities {
  bool descriptorIndexing = false;       // runtime arrays + non-uniform sampled-image indexing
  bool shaderFloat16 = false;
  bool storageBuffer16BitAccess = false;
  bool multiDrawIndirect = false;
  bool drawIndirectCount = false;
  bool fillModeNonSolid = false;         // PipelineDesc::polygonMode other than FILL
  float maxPointSize = 1.0f;             // points larger than one pixel: largePoints, else 1
  bool timestamps = false;
  bool pipelineStatistics = false;       // pipeline-statistics queries (engine/gpu/pipeline_statistics.h)
  float timestampPeriodNs = 1.0f;
  bool isSoftwareRasterizer = false;     // lavapipe & co: timings are CPU-bound
  std::string deviceName;
  // The largest VkBuffer the device creates (Vulkan 1.3 maxBufferSize; at least 2^30): a bigger one
  // is refused by engine::gpu::Buffer with an error naming it, not created.
  VkDeviceSize maxBufferSize = VkDeviceSize(1) << 30;
};

class Context {
 public:
  static Expected<std::unique_ptr<Context>> create(const ContextDesc& desc);
  ~Context();
  Context(const Context&) = delete;
  Context& operator=(const Context&) = delete;

  VkInstance instance() const { return instance_; }
  VkPhysicalDevice physicalDevice() const { return physicalDevice_; }
  VkDevice device() const { return device_; }
  VkQueue queue() const { return queue_; }
  std::uint32_t queueFamily() const { return queueFamily_; }
  const DeviceCapabilities& capabilities() const { return caps_; }
  Allocator& allocator() const { return *allocator_; }
  // Where the pipelines' compiler statistics are recorded, or null when they are off.
  ShaderStatistics* shaderStatistics() const { return shaderStatistics_.get(); }
  // The cache every pipeline is compiled through (engine/gpu/pipeline_cache.h); usable from any thread.
  const PipelineCache& pipelineCache() const { return pipelineCache_; }

  // Validation messages (warnings and errors) seen so far; tests assert this stays 0.
  std::uint32_t validationMessageCount() const { return validationMessages_.load(); }
  std::vector<std::string> validationMessages() const;
  // Validation messages of every context of this process so far, those reported while a context
  // is destroyed included: the layer reports objects never destroyed at vkDestroyDevice, after
  // the last moment anyone can ask the context itself.
  static std::uint64_t processValidationMessageCount();

  // Records commands with `record` into a one-off command buffer, submits and waits. One-off
  // submissions are serialized; the lock and the command buffer are given back however this
  // ends (a failed allocation, a throwing `record`, a failed submission).
  template <class F>
  void submitAndWait(F&& record) const {
    const std::lock_guard lock(oneOffMutex_);
    const OneOffCommands commands(*this);
    record(commands.cmd());
    submitOneOffAndWait(commands.cmd());
  }

  // Gives a Vulkan object a name that validation messages and debuggers show.
  void setName(VkObjectType type, std::uint64_t handle, const std::string& name) const;
  template <class Handle>
  void setName(Handle handle, VkObjectType type, const std::string& name) const {
    setName(type, reinterpret_cast<std::uint64_t>(handle), name);
  }

  void waitIdle() const;

 private:
  Context() = default;
  Status createInstance(const ContextDesc& desc);
  Status pickPhysicalDevice(const ContextDesc& desc);
  Status createDevice(const ContextDesc& desc);
  Status createShaderStatistics(const ContextDesc& desc);
  void savePipelineCache() const noexcept;
  // A begun one-off command buffer, freed by the destructor on every path (with oneOffMutex_ held).
  class OneOffCommands {
   public:
    explicit OneOffCommands(const Context& context);
    ~OneOffCommands();
    OneOffCommands(const OneOffCommands&) = delete;
    OneOffCommands& operator=(const OneOffCommands&) = delete;
    VkCommandBuffer cmd() const { return cmd_; }

   private:
    void free() noexcept;
    const Context& context_;
    VkCommandBuffer cmd_ = VK_NULL_HANDLE;
  };
  void submitOneOffAndWait(VkCommandBuffer cmd) const;
  static VKAPI_ATTR VkBool32 VKAPI_CALL onDebugMessage(VkDebugUtilsMessageSeverityFlagBitsEXT severity,
                                                       VkDebugUtilsMessageTypeFlagsEXT types,
                                                       const VkDebugUtilsMessengerCallbackDataEXT* data,
                                                       void* user);

  VkInstance instance_ = VK_NULL_HANDLE;
  VkDebugUtilsMessengerEXT messenger_ = VK_NULL_HANDLE;
  VkPhysicalDevice physicalDevice_ = VK_NULL_HANDLE;
  VkDevice device_ = VK_NULL_HANDLE;
  VkQueue queue_ = VK_NULL_HANDLE;
  std::uint32_t queueFamily_ = 0;
  VkCommandPool oneOffPool_ = VK_NULL_HANDLE;
  DeviceCapabilities caps_;
  bool debugUtils_ = false;
  PFN_vkSetDebugUtilsObjectNameEXT setObjectName_ = nullptr;
  std::unique_ptr<Allocator> allocator_;
  std::unique_ptr<ShaderStatistics> shaderStatistics_;
  PipelineCache pipelineCache_;
  std::atomic<std::uint32_t> validationMessages_{0};
  mutable std::mutex messagesMutex_;
  std::vector<std::string> messages_;
  mutable std::mutex oneOffMutex_;
};

}  // namespace engine::gpu
