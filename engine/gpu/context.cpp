#include "engine/gpu/context.h"

#include <algorithm>
#include <optional>
#include <cstdlib>
#include <cstring>
#include <string_view>

#include "engine/core/log.h"
#include "engine/gpu/device_features.h"
#include "engine/gpu/device_names.h"
#include "engine/gpu/vk_check.h"

namespace engine::gpu {
namespace {

std::atomic<std::uint64_t> processValidationMessages{0};

constexpr const char* kValidationLayer = "VK_LAYER_KHRONOS_validation";

// An on/off environment variable: unset or empty says nothing; 0, false, off and no are off; any
// other value is on. (HSDF_VALIDATION= and HSDF_VALIDATION=false turned validation on.)
std::optional<bool> envSwitch(const char* name) {
  const char* value = std::getenv(name);
  if (!value || !*value) return std::nullopt;
  const std::string_view v(value);
  return !(v == "0" || v == "false" || v == "off" || v == "no");
}

bool envFlag(const char* name) { return envSwitch(name).value_or(false); }

// The two-call vkEnumerate* idiom, each call checked: a failure (out of memory, a broken layer
// manifest) is an error naming the call, not an empty list that reads as "not installed".
Expected<bool> hasLayer(const char* name) {
  std::uint32_t count = 0;
  VK_TRY(vkEnumerateInstanceLayerProperties(&count, nullptr));
  std::vector<VkLayerProperties> layers(count);
  VK_TRY(vkEnumerateInstanceLayerProperties(&count, layers.data()));
  layers.resize(count);
  return std::any_of(layers.begin(), layers.end(),
                     [&](const VkLayerProperties& l) { return std::strcmp(l.layerName, name) == 0; });
}

Expected<bool> hasInstanceExtension(const char* name) {
  std::uint32_t count = 0;
  VK_TRY(vkEnumerateInstanceExtensionProperties(nullptr, &count, nullptr));
  std::vector<VkExtensionProperties> extensions(count);
  VK_TRY(vkEnumerateInstanceExtensionProperties(nullptr, &count, extensions.data()));
  extensions.resize(count);
  return std::any_of(extensions.begin(), extensions.end(),
                     [&](const VkExtensionProperties& e) { return std::strcmp(e.extensionName, name) == 0; });
}

Expected<bool> hasDeviceExtension(VkPhysicalDevice device, const char* name) {
  std::uint32_t count = 0;
  VK_TRY(vkEnumerateDeviceExtensionProperties(device, nullptr, &count, nullptr));
  std::vector<VkExtensionProperties> extensions(count);
  VK_TRY(vkEnumerateDeviceExtensionProperties(device, nullptr, &count, extensions.data()));
  extensions.resize(count);
  return std::any_of(extensions.begin(), extensions.end(),
                     [&](const VkExtensionProperties& e) { return std::strcmp(e.extensionName, name) == 0; });
}

// Why a device cannot run the engine, or empty when it can.
std::string missingRequirements(VkPhysicalDevice device) {
  VkPhysicalDeviceProperties properties{};
  vkGetPhysicalDeviceProperties(device, &properties);
  if (properties.apiVersion < VK_API_VERSION_1_3) return "Vulkan 1.3 not supported";
  FeatureChain features;
  vkGetPhysicalDeviceFeatures2(device, &features.core);
  return missingRequiredFeatures(features);
}

int deviceRank(VkPhysicalDeviceType type, DevicePreference preference) {
  const bool software = type == VK_PHYSICAL_DEVICE_TYPE_CPU;
  if (preference == DevicePreference::Software) return software ? 0 : -1;
  if (preference == DevicePreference::Hardware && software) return -1;
  switch (type) {
    case VK_PHYSICAL_DEVICE_TYPE_DISCRETE_GPU: return 4;
    case VK_PHYSICAL_DEVICE_TYPE_INTEGRATED_GPU: return 3;
    case VK_PHYSICAL_DEVICE_TYPE_VIRTUAL_GPU: return 2;
    case VK_PHYSICAL_DEVICE_TYPE_CPU: return 1;
    default: return 0;
  }
}

// HSDF_DEVICE decides only what the caller left to Auto (a program's default `--device auto`; the
// test launcher sets it from HSDF_TEST_DEVICE): an explicit choice in the code or on the command
// line wins over the environment. An unknown value is an error, not a silent fallback: a typo must
// not quietly run on another device.
Expected<DevicePreference> preferenceFromEnv(DevicePreference requested) {
  if (requested != DevicePreference::Auto) return requested;
  const char* value = std::getenv("HSDF_DEVICE");
  if (!value || !*value) return requested;
  return parseDeviceName("HSDF_DEVICE", value);
}

const char* preferenceName(DevicePreference preference) {
  switch (preference) {
    case DevicePreference::Hardware: return "a hardware GPU";
    case DevicePreference::Software: return "lavapipe";
    case DevicePreference::Auto: break;
  }
  return "auto";
}

// Which validation the instance gets: the layers as the description asks, and the features that
// slow every call or shader down only where asked for.
struct ValidationChoice {
  bool layers = false;
  bool sync = false;
  bool gpuAssisted = false;

  std::vector<VkValidationFeatureEnableEXT> featureEnables() const {
    std::vector<VkValidationFeatureEnableEXT> enables;
    if (sync) enables.push_back(VK_VALIDATION_FEATURE_ENABLE_SYNCHRONIZATION_VALIDATION_EXT);
    if (gpuAssisted) enables.push_back(VK_VALIDATION_FEATURE_ENABLE_GPU_ASSISTED_EXT);
    return enables;
  }

  void report() const {
    if (sync || gpuAssisted)  // in the log of every test the CI's validation stage runs
      log::info("validation layers on{}{}", sync ? ", synchronization validation" : "",
                gpuAssisted ? ", GPU-assisted validation" : "");
    else if (layers)
      log::debug("validation layers on");
  }
};

ValidationChoice chooseValidation(const ContextDesc& desc) {
  ValidationChoice choice;
  choice.layers = desc.validation;
  choice.sync = choice.layers && (desc.synchronizationValidation || envFlag("HSDF_SYNC_VALIDATION"));
  // GPU-assisted validation (the layer instruments every shader: out-of-bounds descriptor indices
  // and buffer-device-address accesses are reported) only from the environment: the CI's
  // validation stage sets it (scripts/test.sh); it slows shaders down several times.
  choice.gpuAssisted = choice.layers && envFlag("HSDF_GPU_ASSISTED_VALIDATION");
  return choice;
}

Status checkValidationLayer() {
  ENGINE_TRY_ASSIGN(const bool installed, hasLayer(kValidationLayer));
  if (!installed)
    return makeError("validation requested but VK_LAYER_KHRONOS_validation is not installed "
                     "(Debian package vulkan-validationlayers)");
  return {};
}

// Every message of every kind, to `callback` (which counts the warnings and errors).
VkDebugUtilsMessengerCreateInfoEXT debugMessengerInfo(PFN_vkDebugUtilsMessengerCallbackEXT callback, void* user) {
  VkDebugUtilsMessengerCreateInfoEXT info{VK_STRUCTURE_TYPE_DEBUG_UTILS_MESSENGER_CREATE_INFO_EXT};
  info.messageSeverity = VK_DEBUG_UTILS_MESSAGE_SEVERITY_VERBOSE_BIT_EXT | VK_DEBUG_UTILS_MESSAGE_SEVERITY_INFO_BIT_EXT |
                         VK_DEBUG_UTILS_MESSAGE_SEVERITY_WARNING_BIT_EXT | VK_DEBUG_UTILS_MESSAGE_SEVERITY_ERROR_BIT_EXT;
  info.messageType = VK_DEBUG_UTILS_MESSAGE_TYPE_GENERAL_BIT_EXT | VK_DEBUG_UTILS_MESSAGE_TYPE_VALIDATION_BIT_EXT |
                     VK_DEBUG_UTILS_MESSAGE_TYPE_PERFORMANCE_BIT_EXT;
  info.pfnUserCallback = callback;
  info.pUserData = user;
  return info;
}

// The instance's pNext chain of those given (null: left out): the validation features, then the messenger.
const void* instanceChain(VkDebugUtilsMessengerCreateInfoEXT* messenger, VkValidationFeaturesEXT* features) {
  const void* chain = nullptr;
  if (messenger) {
    messenger->pNext = chain;
    chain = messenger;
  }
  if (features) {
    features->pNext = chain;
    chain = features;
  }
  return chain;
}

Status createVulkanInstance(const VkInstanceCreateInfo& info, VkInstance& instance) {
  // No driver at all is the likely reason for this one result: say so, not only the code.
  if (const VkResult created = vkCreateInstance(&info, nullptr, &instance); created == VK_ERROR_INCOMPATIBLE_DRIVER)
    return makeError("no Vulkan driver found (vkCreateInstance: VK_ERROR_INCOMPATIBLE_DRIVER): install "
                     "mesa-vulkan-drivers (lavapipe) or a GPU's driver, and check VK_ICD_FILENAMES / "
                     "VK_DRIVER_FILES if they are set");
  else
    VK_TRY(created);
  return {};
}

// The messenger that outlives instance creation (the one in the instance's chain serves only that).
Status createMessenger(VkInstance instance, VkDebugUtilsMessengerCreateInfoEXT info, VkDebugUtilsMessengerEXT& messenger) {
  info.pNext = nullptr;
  auto create = reinterpret_cast<PFN_vkCreateDebugUtilsMessengerEXT>(
      vkGetInstanceProcAddr(instance, "vkCreateDebugUtilsMessengerEXT"));
  if (create) VK_TRY(create(instance, &info, nullptr, &messenger));
  return {};
}

// What the device offers that the renderer and its features choose by (all but timestamps, which
// depend on the queue family).
void readCapabilities(VkPhysicalDevice device, const VkPhysicalDeviceProperties& properties,
                      FeatureChain& supported, DeviceCapabilities& caps) {
  VkPhysicalDeviceVulkan13Properties properties13{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_3_PROPERTIES};
  VkPhysicalDeviceProperties2 properties2{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_PROPERTIES_2};
  properties2.pNext = &properties13;
  vkGetPhysicalDeviceProperties2(device, &properties2);
  caps.maxBufferSize = std::max(properties13.maxBufferSize, caps.maxBufferSize);
  caps.deviceName = properties.deviceName;
  caps.isSoftwareRasterizer = properties.deviceType == VK_PHYSICAL_DEVICE_TYPE_CPU;
  caps.descriptorIndexing = hasDescriptorIndexing(supported);
  caps.shaderFloat16 = supported.v12.shaderFloat16;
  caps.storageBuffer16BitAccess = supported.v11.storageBuffer16BitAccess;
  caps.multiDrawIndirect = supported.core.features.multiDrawIndirect;
  caps.drawIndirectCount = supported.v12.drawIndirectCount;
  caps.fillModeNonSolid = supported.core.features.fillModeNonSolid;
  caps.maxPointSize = supported.core.features.largePoints ? properties.limits.pointSizeRange[1] : 1.0f;
  caps.pipelineStatistics = supported.core.features.pipelineStatisticsQuery;
  caps.timestampPeriodNs = properties.limits.timestampPeriod;
}

struct QueueFamily {
  std::uint32_t index = 0;
  std::uint32_t timestampValidBits = 0;
};

// The first family with graphics (graphics queues can also compute and transfer).
std::optional<QueueFamily> graphicsQueueFamily(VkPhysicalDevice device) {
  std::uint32_t familyCount = 0;
  vkGetPhysicalDeviceQueueFamilyProperties(device, &familyCount, nullptr);
  std::vector<VkQueueFamilyProperties> families(familyCount);
  vkGetPhysicalDeviceQueueFamilyProperties(device, &familyCount, families.data());
  for (std::uint32_t i = 0; i < familyCount; ++i)
    if (families[i].queueFlags & VK_QUEUE_GRAPHICS_BIT) return QueueFamily{i, families[i].timestampValidBits};
  return std::nullopt;
}

// Native shader statistics read the driver's own compiler statistics, through this extension.
Status requireExecutableProperties(VkPhysicalDevice device, const std::string& deviceName) {
  ENGINE_TRY_ASSIGN(const bool has, hasDeviceExtension(device, VK_KHR_PIPELINE_EXECUTABLE_PROPERTIES_EXTENSION_NAME));
  if (!has)
    return makeError("shader statistics: " + deviceName + " has no " +
                     VK_KHR_PIPELINE_EXECUTABLE_PROPERTIES_EXTENSION_NAME + " (a statistics device can compile them instead)");
  return {};
}

}  // namespace

bool ContextDesc::defaultValidation() {
  if (const std::optional<bool> set = envSwitch("HSDF_VALIDATION")) return *set;
#ifdef NDEBUG
  return false;
#else
  return true;
#endif
}

Expected<std::unique_ptr<Context>> Context::create(const ContextDesc& desc) {
  std::unique_ptr<Context> context(new Context());
  ENGINE_TRY(context->createInstance(desc));
  ENGINE_TRY(context->pickPhysicalDevice(desc));
  ENGINE_TRY(context->createDevice(desc));
  ENGINE_TRY(context->createShaderStatistics(desc));
  ENGINE_TRY_ASSIGN(context->pipelineCache_, PipelineCache::create(context->device_, pipelineCacheIdentity(context->physicalDevice_),
                                                                   desc.pipelineCacheFile));
  return context;
}

// A cache that cannot be written costs the next run its compiles, not this run anything: logged.
void Context::savePipelineCache() const noexcept {
  try {
    if (const Status saved = pipelineCache_.save(); !saved)
      log::warn("pipeline cache not saved: {}", saved.error().message);
  } catch (const std::exception& error) {
    log::warn("pipeline cache not saved: {}", error.what());
  }
}

Context::~Context() {
  shaderStatistics_.reset();  // its device, if any, belongs to the instance destroyed below
  if (device_) {
    vkDeviceWaitIdle(device_);
    savePipelineCache();
    pipelineCache_ = PipelineCache();
    allocator_.reset();
    if (oneOffPool_) vkDestroyCommandPool(device_, oneOffPool_, nullptr);
    vkDestroyDevice(device_, nullptr);
  }
  if (messenger_) {
    auto destroy = reinterpret_cast<PFN_vkDestroyDebugUtilsMessengerEXT>(
        vkGetInstanceProcAddr(instance_, "vkDestroyDebugUtilsMessengerEXT"));
    if (destroy) destroy(instance_, messenger_, nullptr);
  }
  if (instance_) vkDestroyInstance(instance_, nullptr);
}

VKAPI_ATTR VkBool32 VKAPI_CALL Context::onDebugMessage(VkDebugUtilsMessageSeverityFlagBitsEXT severity,
                                                       VkDebugUtilsMessageTypeFlagsEXT /*types*/,
                                                       const VkDebugUtilsMessengerCallbackDataEXT* data,
                                                       void* user) {
  auto* self = static_cast<Context*>(user);
  const char* text = data && data->pMessage ? data->pMessage : "(no message)";
  if (severity >= VK_DEBUG_UTILS_MESSAGE_SEVERITY_WARNING_BIT_EXT) {
    self->validationMessages_.fetch_add(1);
    processValidationMessages.fetch_add(1);
    {
      std::lock_guard lock(self->messagesMutex_);
      if (self->messages_.size() < 64) self->messages_.emplace_back(text);
    }
    if (severity >= VK_DEBUG_UTILS_MESSAGE_SEVERITY_ERROR_BIT_EXT)
      log::error("vulkan: {}", text);
    else
      log::warn("vulkan: {}", text);
  } else {
    log::debug("vulkan: {}", text);
  }
  return VK_FALSE;
}

std::uint64_t Context::processValidationMessageCount() { return processValidationMessages.load(); }

std::vector<std::string> Context::validationMessages() const {
  std::lock_guard lock(messagesMutex_);
  return messages_;
}

Status Context::createInstance(const ContextDesc& desc) {
  const ValidationChoice validation = chooseValidation(desc);
  std::vector<const char*> layers;
  if (validation.layers) {
    ENGINE_TRY(checkValidationLayer());
    layers.push_back(kValidationLayer);
  }
  std::vector<const char*> extensions;
  for (const std::string& e : desc.instanceExtensions) extensions.push_back(e.c_str());
  ENGINE_TRY_ASSIGN(debugUtils_, hasInstanceExtension(VK_EXT_DEBUG_UTILS_EXTENSION_NAME));
  if (debugUtils_) extensions.push_back(VK_EXT_DEBUG_UTILS_EXTENSION_NAME);

  VkApplicationInfo app{VK_STRUCTURE_TYPE_APPLICATION_INFO};
  app.pApplicationName = desc.applicationName.c_str();
  app.pEngineName = desc.engineName.c_str();
  app.apiVersion = VK_API_VERSION_1_3;
  VkDebugUtilsMessengerCreateInfoEXT messengerInfo = debugMessengerInfo(&Context::onDebugMessage, this);
  const std::vector<VkValidationFeatureEnableEXT> enables = validation.featureEnables();
  VkValidationFeaturesEXT validationFeatures{VK_STRUCTURE_TYPE_VALIDATION_FEATURES_EXT};
  validationFeatures.enabledValidationFeatureCount = static_cast<std::uint32_t>(enables.size());
  validationFeatures.pEnabledValidationFeatures = enables.data();

  VkInstanceCreateInfo info{VK_STRUCTURE_TYPE_INSTANCE_CREATE_INFO};
  info.pApplicationInfo = &app;
  info.enabledLayerCount = static_cast<std::uint32_t>(layers.size());
  info.ppEnabledLayerNames = layers.data();
  info.enabledExtensionCount = static_cast<std::uint32_t>(extensions.size());
  info.ppEnabledExtensionNames = extensions.data();
  // Messages from instance creation itself go to the same callback.
  info.pNext = instanceChain(debugUtils_ ? &messengerInfo : nullptr, enables.empty() ? nullptr : &validationFeatures);
  ENGINE_TRY(createVulkanInstance(info, instance_));

  if (debugUtils_) {
    ENGINE_TRY(createMessenger(instance_, messengerInfo, messenger_));
    setObjectName_ = reinterpret_cast<PFN_vkSetDebugUtilsObjectNameEXT>(
        vkGetInstanceProcAddr(instance_, "vkSetDebugUtilsObjectNameEXT"));
  }
  validation.report();
  return {};
}

Status Context::pickPhysicalDevice(const ContextDesc& desc) {
  std::uint32_t count = 0;
  VK_TRY(vkEnumeratePhysicalDevices(instance_, &count, nullptr));
  std::vector<VkPhysicalDevice> devices(count);
  VK_TRY(vkEnumeratePhysicalDevices(instance_, &count, devices.data()));
  ENGINE_TRY_ASSIGN(const DevicePreference preference, preferenceFromEnv(desc.device));

  std::string rejected;
  int bestRank = -1;
  for (VkPhysicalDevice device : devices) {
    VkPhysicalDeviceProperties properties{};
    vkGetPhysicalDeviceProperties(device, &properties);
    std::string why = missingRequirements(device);
    if (why.empty() && isNullDevice(properties.deviceName))
      why = "a null device: it compiles pipelines but cannot run them (RADV_FORCE_FAMILY is set); it serves only "
            "as a shader statistics device";
    if (desc.swapchain && why.empty()) {
      ENGINE_TRY_ASSIGN(const bool canPresent, hasDeviceExtension(device, VK_KHR_SWAPCHAIN_EXTENSION_NAME));
      if (!canPresent) why = "no VK_KHR_swapchain";
    }
    const int rank = deviceRank(properties.deviceType, preference);
    if (!why.empty() || rank < 0) {
      rejected += std::string("\n  ") + properties.deviceName + ": " +
                  (why.empty() ? std::string("not the kind asked for (") + preferenceName(preference) + ")" : why);
      continue;
    }
    if (rank > bestRank) {
      bestRank = rank;
      physicalDevice_ = device;
    }
  }
  if (!physicalDevice_ && preference == DevicePreference::Hardware)
    return makeError("no hardware GPU with " + describeRequirements() +
                     " was found; --device lavapipe or auto draws on the CPU" + rejected);
  if (!physicalDevice_)
    return makeError("no suitable Vulkan device (need " + describeRequirements() +
                     "; install mesa-vulkan-drivers for lavapipe)" + rejected);
  return {};
}

Status Context::createDevice(const ContextDesc& desc) {
  VkPhysicalDeviceProperties properties{};
  vkGetPhysicalDeviceProperties(physicalDevice_, &properties);
  FeatureChain supported;
  vkGetPhysicalDeviceFeatures2(physicalDevice_, &supported.core);
  readCapabilities(physicalDevice_, properties, supported, caps_);
  const std::optional<QueueFamily> family = graphicsQueueFamily(physicalDevice_);
  if (!family) return makeError(caps_.deviceName + ": no graphics queue");
  queueFamily_ = family->index;
  caps_.timestamps = family->timestampValidBits > 0 && properties.limits.timestampComputeAndGraphics;

  // The required features (device_features.h), then the optional ones the device has.
  FeatureChain enabled;
  enableRequiredFeatures(enabled);
  enableOptionalFeatures(enabled, supported);
  std::vector<const char*> extensions;
  if (desc.swapchain) extensions.push_back(VK_KHR_SWAPCHAIN_EXTENSION_NAME);
  VkPhysicalDevicePipelineExecutablePropertiesFeaturesKHR executable{
      VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_PIPELINE_EXECUTABLE_PROPERTIES_FEATURES_KHR};
  if (desc.shaderStatistics.target == StatisticsTarget::Native) {
    ENGINE_TRY(requireExecutableProperties(physicalDevice_, caps_.deviceName));
    extensions.push_back(VK_KHR_PIPELINE_EXECUTABLE_PROPERTIES_EXTENSION_NAME);
    executable.pipelineExecutableInfo = VK_TRUE;
    enabled.v13.pNext = &executable;
  }

  const float priority = 1.0f;
  VkDeviceQueueCreateInfo queueInfo{VK_STRUCTURE_TYPE_DEVICE_QUEUE_CREATE_INFO};
  queueInfo.queueFamilyIndex = queueFamily_;
  queueInfo.queueCount = 1;
  queueInfo.pQueuePriorities = &priority;
  VkDeviceCreateInfo info{VK_STRUCTURE_TYPE_DEVICE_CREATE_INFO};
  info.pNext = &enabled.core;
  info.queueCreateInfoCount = 1;
  info.pQueueCreateInfos = &queueInfo;
  info.enabledExtensionCount = static_cast<std::uint32_t>(extensions.size());
  info.ppEnabledExtensionNames = extensions.data();
  VK_TRY(vkCreateDevice(physicalDevice_, &info, nullptr, &device_));
  vkGetDeviceQueue(device_, queueFamily_, 0, &queue_);
  allocator_ = std::make_unique<Allocator>(physicalDevice_, device_);
  VkCommandPoolCreateInfo poolInfo{VK_STRUCTURE_TYPE_COMMAND_POOL_CREATE_INFO};
  poolInfo.flags = VK_COMMAND_POOL_CREATE_TRANSIENT_BIT;
  poolInfo.queueFamilyIndex = queueFamily_;
  VK_TRY(vkCreateCommandPool(device_, &poolInfo, nullptr, &oneOffPool_));
  setName(oneOffPool_, VK_OBJECT_TYPE_COMMAND_POOL, "one-off command pool");
  setName(queue_, VK_OBJECT_TYPE_QUEUE, "graphics queue");
  log::info("Vulkan device: {}{}", caps_.deviceName, caps_.isSoftwareRasterizer ? " (software)" : "");
  return {};
}

Status Context::createShaderStatistics(const ContextDesc& desc) {
  switch (desc.shaderStatistics.target) {
    case StatisticsTarget::Off: return {};
    case StatisticsTarget::Native: shaderStatistics_ = ShaderStatistics::createNative(device_, caps_.deviceName); break;
    case StatisticsTarget::Device: {
      ENGINE_TRY_ASSIGN(shaderStatistics_, ShaderStatistics::createOnDevice(instance_, desc.shaderStatistics));
      break;
    }
  }
  log::info("shader statistics from {}", shaderStatistics_->deviceName());
  return {};
}

void Context::setName(VkObjectType type, std::uint64_t handle, const std::string& name) const {
  if (!setObjectName_ || handle == 0) return;
  VkDebugUtilsObjectNameInfoEXT info{VK_STRUCTURE_TYPE_DEBUG_UTILS_OBJECT_NAME_INFO_EXT};
  info.objectType = type;
  info.objectHandle = handle;
  info.pObjectName = name.c_str();
  VK_CHECK(setObjectName_(device_, &info));
}

Context::OneOffCommands::OneOffCommands(const Context& context) : context_(context) {
  VkCommandBufferAllocateInfo info{VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO};
  info.commandPool = context.oneOffPool_;
  info.level = VK_COMMAND_BUFFER_LEVEL_PRIMARY;
  info.commandBufferCount = 1;
  try {  // a constructor that throws runs no destructor
    VK_CHECK(vkAllocateCommandBuffers(context.device_, &info, &cmd_));
    VkCommandBufferBeginInfo begin{VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO};
    begin.flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT;
    VK_CHECK(vkBeginCommandBuffer(cmd_, &begin));
  } catch (...) {
    free();
    throw;
  }
}

Context::OneOffCommands::~OneOffCommands() { free(); }

// A failed vkAllocateCommandBuffers leaves the handle null (nothing to free); fault injection
// reports a failure for one the driver did allocate.
void Context::OneOffCommands::free() noexcept {
  if (cmd_) vkFreeCommandBuffers(context_.device_, context_.oneOffPool_, 1, &cmd_);
  cmd_ = VK_NULL_HANDLE;
}

void Context::submitOneOffAndWait(VkCommandBuffer cmd) const {
  VkFence fence = VK_NULL_HANDLE;
  try {  // a failed call (a lost device, no memory for the fence) must not leak the fence
    VK_CHECK(vkEndCommandBuffer(cmd));
    VkFenceCreateInfo fenceInfo{VK_STRUCTURE_TYPE_FENCE_CREATE_INFO};
    VK_CHECK(vkCreateFence(device_, &fenceInfo, nullptr, &fence));
    VkCommandBufferSubmitInfo cmdInfo{VK_STRUCTURE_TYPE_COMMAND_BUFFER_SUBMIT_INFO};
    cmdInfo.commandBuffer = cmd;
    VkSubmitInfo2 submit{VK_STRUCTURE_TYPE_SUBMIT_INFO_2};
    submit.commandBufferInfoCount = 1;
    submit.pCommandBufferInfos = &cmdInfo;
    VK_CHECK(vkQueueSubmit2(queue_, 1, &submit, fence));
    VK_CHECK(vkWaitForFences(device_, 1, &fence, VK_TRUE, UINT64_MAX));
  } catch (...) {
    // What was submitted may still run (its command buffer is freed after this); a lost device
    // returns at once.
    vkQueueWaitIdle(queue_);
    if (fence) vkDestroyFence(device_, fence, nullptr);
    throw;
  }
  vkDestroyFence(device_, fence, nullptr);
}

void Context::waitIdle() const { VK_CHECK(vkDeviceWaitIdle(device_)); }

}  // namespace engine::gpu
