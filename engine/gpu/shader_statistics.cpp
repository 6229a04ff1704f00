#include "engine/gpu/shader_statistics.h"

#include <algorithm>

#include "engine/gpu/device_features.h"
#include "engine/gpu/vk_check.h"

namespace engine::gpu {
namespace {

std::string stageName(VkShaderStageFlags stages) {
  switch (stages) {
    case VK_SHADER_STAGE_VERTEX_BIT: return "vertex";
    case VK_SHADER_STAGE_FRAGMENT_BIT: return "fragment";
    case VK_SHADER_STAGE_COMPUTE_BIT: return "compute";
    default: return "stages " + std::to_string(stages);
  }
}

double statisticValue(const VkPipelineExecutableStatisticKHR& statistic) {
  switch (statistic.format) {
    case VK_PIPELINE_EXECUTABLE_STATISTIC_FORMAT_BOOL32_KHR: return statistic.value.b32 ? 1.0 : 0.0;
    case VK_PIPELINE_EXECUTABLE_STATISTIC_FORMAT_INT64_KHR: return double(statistic.value.i64);
    case VK_PIPELINE_EXECUTABLE_STATISTIC_FORMAT_UINT64_KHR: return double(statistic.value.u64);
    default: return statistic.value.f64;
  }
}

Expected<std::vector<VkPhysicalDevice>> physicalDevices(VkInstance instance) {
  std::uint32_t count = 0;
  VK_TRY(vkEnumeratePhysicalDevices(instance, &count, nullptr));
  std::vector<VkPhysicalDevice> devices(count);
  VK_TRY(vkEnumeratePhysicalDevices(instance, &count, devices.data()));
  devices.resize(count);
  return devices;
}

std::string physicalDeviceName(VkPhysicalDevice device) {
  VkPhysicalDeviceProperties properties{};
  vkGetPhysicalDeviceProperties(device, &properties);
  return properties.deviceName;
}

Expected<bool> hasExecutableProperties(VkPhysicalDevice device) {
  std::uint32_t count = 0;
  VK_TRY(vkEnumerateDeviceExtensionProperties(device, nullptr, &count, nullptr));
  std::vector<VkExtensionProperties> extensions(count);
  VK_TRY(vkEnumerateDeviceExtensionProperties(device, nullptr, &count, extensions.data()));
  return std::any_of(extensions.begin(), extensions.begin() + count, [](const VkExtensionProperties& e) {
    return std::string_view(e.extensionName) == VK_KHR_PIPELINE_EXECUTABLE_PROPERTIES_EXTENSION_NAME;
  });
}

// The first device whose name holds `part`; the error lists the names there are.
Expected<VkPhysicalDevice> findDevice(VkInstance instance, const std::string& part) {
  ENGINE_TRY_ASSIGN(const std::vector<VkPhysicalDevice> devices, physicalDevices(instance));
  std::string names;
  for (VkPhysicalDevice device : devices) {
    const std::string name = physicalDeviceName(device);
    if (!part.empty() && name.find(part) != std::string::npos) return device;
    names += (names.empty() ? "" : ", ") + name;
  }
  return makeError("shader statistics: no Vulkan device named '*" + part + "*' (there are: " + names +
                   "); Mesa's RADV shows a null device of an AMD GPU family when RADV_FORCE_FAMILY is set "
                   "(e.g. RADV_FORCE_FAMILY=navi10) and mesa-vulkan-drivers is installed");
}

}  // namespace

bool isNullDevice(std::string_view deviceName) { return deviceName.starts_with("Null hardware"); }

std::optional<double> StageStatistics::value(std::string_view name) const {
  for (const auto& [key, number] : values)
    if (key == name) return number;
  return std::nullopt;
}

std::unique_ptr<ShaderStatistics> ShaderStatistics::createNative(VkDevice device, std::string deviceName) {
  std::unique_ptr<ShaderStatistics> statistics(new ShaderStatistics());
  statistics->target_ = StatisticsTarget::Native;
  statistics->deviceName_ = std::move(deviceName);
  statistics->device_ = device;
  statistics->getExecutables_ = reinterpret_cast<PFN_vkGetPipelineExecutablePropertiesKHR>(
      vkGetDeviceProcAddr(device, "vkGetPipelineExecutablePropertiesKHR"));
  statistics->getStatistics_ = reinterpret_cast<PFN_vkGetPipelineExecutableStatisticsKHR>(
      vkGetDeviceProcAddr(device, "vkGetPipelineExecutableStatisticsKHR"));
  return statistics;
}

Expected<std::unique_ptr<ShaderStatistics>> ShaderStatistics::createOnDevice(VkInstance instance,
                                                                           const ShaderStatisticsDesc& desc) {
  ENGINE_TRY_ASSIGN(const VkPhysicalDevice physicalDevice, findDevice(instance, desc.deviceName));
  std::unique_ptr<ShaderStatistics> statistics(new ShaderStatistics());
  statistics->target_ = StatisticsTarget::Device;
  statistics->deviceName_ = physicalDeviceName(physicalDevice);
  ENGINE_TRY_ASSIGN(const bool executable, hasExecutableProperties(physicalDevice));
  if (!executable)
    return makeError("shader statistics: " + statistics->deviceName_ + " has no " +
                     VK_KHR_PIPELINE_EXECUTABLE_PROPERTIES_EXTENSION_NAME);
  ENGINE_TRY(statistics->createDevice(physicalDevice));
  return statistics;
}

// The features enabled are those of the rendering device (device_features.h): the same SPIR-V
// must compile, and a feature such as robust buffer access would change the code compiled.
Status ShaderStatistics::createDevice(VkPhysicalDevice physicalDevice) {
  FeatureChain supported;
  vkGetPhysicalDeviceFeatures2(physicalDevice, &supported.core);
  if (const std::string missing = missingRequiredFeatures(supported); !missing.empty())
    return makeError("shader statistics: " + deviceName_ + " lacks what the engine's shaders need: " + missing);
  FeatureChain enabled;
  enableRequiredFeatures(enabled);
  enableOptionalFeatures(enabled, supported);
  VkPhysicalDevicePipelineExecutablePropertiesFeaturesKHR executable{
      VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_PIPELINE_EXECUTABLE_PROPERTIES_FEATURES_KHR};
  executable.pipelineExecutableInfo = VK_TRUE;
  enabled.v13.pNext = &executable;

  const float priority = 1.0f;
  VkDeviceQueueCreateInfo queue{VK_STRUCTURE_TYPE_DEVICE_QUEUE_CREATE_INFO};
  queue.queueCount = 1;  // family 0: a device must have a queue, though this one never submits
  queue.pQueuePriorities = &priority;
  const char* extension = VK_KHR_PIPELINE_EXECUTABLE_PROPERTIES_EXTENSION_NAME;
  VkDeviceCreateInfo info{VK_STRUCTURE_TYPE_DEVICE_CREATE_INFO};
  info.pNext = &enabled.core;
  info.queueCreateInfoCount = 1;
  info.pQueueCreateInfos = &queue;
  info.enabledExtensionCount = 1;
  info.ppEnabledExtensionNames = &extension;
  VK_TRY(vkCreateDevice(physicalDevice, &info, nullptr, &device_));
  ownsDevice_ = true;
  getExecutables_ = reinterpret_cast<PFN_vkGetPipelineExecutablePropertiesKHR>(
      vkGetDeviceProcAddr(device_, "vkGetPipelineExecutablePropertiesKHR"));
  getStatistics_ = reinterpret_cast<PFN_vkGetPipelineExecutableStatisticsKHR>(
      vkGetDeviceProcAddr(device_, "vkGetPipelineExecutableStatisticsKHR"));
  return {};
}

ShaderStatistics::~ShaderStatistics() {
  if (!ownsDevice_) return;
  for (const auto& [module, shader] : shaders_) vkDestroyShaderModule(device_, shader.copy, nullptr);
  for (const auto& [layout, copy] : setLayouts_) vkDestroyDescriptorSetLayout(device_, copy, nullptr);
  vkDestroyDevice(device_, nullptr);
}

Status ShaderStatistics::addShader(VkShaderModule module, const std::string& name, std::span<const std::uint8_t> spirv) {
  Shader shader{name};
  if (target_ == StatisticsTarget::Device) {
    VkShaderModuleCreateInfo info{VK_STRUCTURE_TYPE_SHADER_MODULE_CREATE_INFO};
    info.codeSize = spirv.size();
    info.pCode = reinterpret_cast<const std::uint32_t*>(spirv.data());
    VK_TRY(vkCreateShaderModule(device_, &info, nullptr, &shader.copy));
  }
  const std::lock_guard lock(mutex_);
  shaders_[module] = std::move(shader);
  return {};
}

void ShaderStatistics::removeShader(VkShaderModule module) {
  const std::lock_guard lock(mutex_);
  const auto found = shaders_.find(module);
  if (found == shaders_.end()) return;
  if (ownsDevice_) vkDestroyShaderModule(device_, found->second.copy, nullptr);
  shaders_.erase(found);
}

Status ShaderStatistics::addSetLayout(VkDescriptorSetLayout layout, const VkDescriptorSetLayoutCreateInfo& info) {
  if (target_ != StatisticsTarget::Device) return {};
  for (std::uint32_t i = 0; i < info.bindingCount; ++i)
    if (info.pBindings[i].pImmutableSamplers)
      return makeError("shader statistics: a set layout with immutable samplers cannot be copied to " + deviceName_);
  VkDescriptorSetLayout copy = VK_NULL_HANDLE;
  VK_TRY(vkCreateDescriptorSetLayout(device_, &info, nullptr, &copy));
  const std::lock_guard lock(mutex_);
  setLayouts_[layout] = copy;
  return {};
}

void ShaderStatistics::removeSetLayout(VkDescriptorSetLayout layout) {
  const std::lock_guard lock(mutex_);
  const auto found = setLayouts_.find(layout);
  if (found == setLayouts_.end()) return;
  vkDestroyDescriptorSetLayout(device_, found->second, nullptr);
  setLayouts_.erase(found);
}

VkPipelineCreateFlags ShaderStatistics::pipelineFlags() const {
  return target_ == StatisticsTarget::Native ? VK_PIPELINE_CREATE_CAPTURE_STATISTICS_BIT_KHR : 0;
}

void ShaderStatistics::record(const std::string& name, const VkGraphicsPipelineCreateInfo& info,
                              const VkPipelineLayoutCreateInfo& layout, VkPipeline pipeline) {
  const std::lock_guard lock(mutex_);
  const std::span<const VkPipelineShaderStageCreateInfo> stages(info.pStages, info.stageCount);
  store(name, target_ == StatisticsTarget::Native ? readNative(pipeline, stages) : readCopy(info, layout, stages));
}

void ShaderStatistics::record(const std::string& name, const VkComputePipelineCreateInfo& info,
                              const VkPipelineLayoutCreateInfo& layout, VkPipeline pipeline) {
  const std::lock_guard lock(mutex_);
  const std::span<const VkPipelineShaderStageCreateInfo> stages(&info.stage, 1);
  store(name, target_ == StatisticsTarget::Native ? readNative(pipeline, stages) : readCopy(info, layout, stages));
}

// One row per stage of a pipeline the statistics device could not compile or read, saying why.
std::vector<StageStatistics> ShaderStatistics::failedStages(std::span<const VkPipelineShaderStageCreateInfo> stages,
                                                            const std::string& why) const {
  std::vector<StageStatistics> rows;
  for (const VkPipelineShaderStageCreateInfo& stage : stages)
    rows.push_back({{}, stageName(stage.stage), shaderNames(stage.stage, stages), {}, why});
  return rows;
}

std::vector<StageStatistics> ShaderStatistics::readNative(VkPipeline pipeline,
                                                          std::span<const VkPipelineShaderStageCreateInfo> stages) const {
  auto read = readStages(pipeline, stages);
  return read ? std::move(*read) : failedStages(stages, read.error().message);
}

template <class Info>
std::vector<StageStatistics> ShaderStatistics::readCopy(const Info& info, const VkPipelineLayoutCreateInfo& layout,
                                                        std::span<const VkPipelineShaderStageCreateInfo> stages) const {
  const auto layoutCopy = copyLayout(layout);
  if (!layoutCopy) return failedStages(stages, layoutCopy.error().message);
  const auto copy = compileCopy(info, *layoutCopy);
  std::vector<StageStatistics> rows = copy ? readNative(*copy, stages) : failedStages(stages, copy.error().message);
  if (copy) vkDestroyPipeline(device_, *copy, nullptr);
  vkDestroyPipelineLayout(device_, *layoutCopy, nullptr);
  return rows;
}

Expected<VkPipelineLayout> ShaderStatistics::copyLayout(const VkPipelineLayoutCreateInfo& info) const {
  std::vector<VkDescriptorSetLayout> sets;
  for (std::uint32_t i = 0; i < info.setLayoutCount; ++i) {
    const auto found = setLayouts_.find(info.pSetLayouts[i]);
    if (found == setLayouts_.end())
      return makeError("shader statistics: a set layout not made by engine::gpu::DescriptorSetLayout");
    sets.push_back(found->second);
  }
  VkPipelineLayoutCreateInfo copy = info;
  copy.pSetLayouts = sets.data();
  VkPipelineLayout layout = VK_NULL_HANDLE;
  VK_TRY(vkCreatePipelineLayout(device_, &copy, nullptr, &layout));
  return layout;
}

Expected<VkShaderModule> ShaderStatistics::copiedModule(VkShaderModule module) const {
  const auto found = shaders_.find(module);
  if (found == shaders_.end()) return makeError("shader statistics: a shader module not loaded by engine::gpu::ShaderModule");
  return found->second.copy;
}

Expected<VkPipeline> ShaderStatistics::compileCopy(VkGraphicsPipelineCreateInfo info, VkPipelineLayout layout) const {
  std::vector<VkPipelineShaderStageCreateInfo> stages(info.pStages, info.pStages + info.stageCount);
  for (VkPipelineShaderStageCreateInfo& stage : stages) {
    ENGINE_TRY_ASSIGN(stage.module, copiedModule(stage.module));
  }
  info.pStages = stages.data();
  info.layout = layout;
  info.flags |= VK_PIPELINE_CREATE_CAPTURE_STATISTICS_BIT_KHR;
  VkPipeline pipeline = VK_NULL_HANDLE;
  VK_TRY(vkCreateGraphicsPipelines(device_, VK_NULL_HANDLE, 1, &info, nullptr, &pipeline));
  return pipeline;
}

Expected<VkPipeline> ShaderStatistics::compileCopy(VkComputePipelineCreateInfo info, VkPipelineLayout layout) const {
  ENGINE_TRY_ASSIGN(info.stage.module, copiedModule(info.stage.module));
  info.layout = layout;
  info.flags |= VK_PIPELINE_CREATE_CAPTURE_STATISTICS_BIT_KHR;
  VkPipeline pipeline = VK_NULL_HANDLE;
  VK_TRY(vkCreateComputePipelines(device_, VK_NULL_HANDLE, 1, &info, nullptr, &pipeline));
  return pipeline;
}

// The shaders a driver's executable was compiled from (several where it merged stages).
std::string ShaderStatistics::shaderNames(VkShaderStageFlags executableStages,
                                          std::span<const VkPipelineShaderStageCreateInfo> stages) const {
  std::string names;
  for (const VkPipelineShaderStageCreateInfo& stage : stages) {
    if (!(stage.stage & executableStages)) continue;
    const auto found = shaders_.find(stage.module);
    names += (names.empty() ? "" : "+") + (found == shaders_.end() ? std::string("?") : found->second.name);
  }
  return names;
}

Expected<std::vector<StageStatistics>> ShaderStatistics::readStages(
    VkPipeline pipeline, std::span<const VkPipelineShaderStageCreateInfo> stages) const {
  VkPipelineInfoKHR pipelineInfo{VK_STRUCTURE_TYPE_PIPELINE_INFO_KHR};
  pipelineInfo.pipeline = pipeline;
  std::uint32_t count = 0;
  VK_TRY(getExecutables_(device_, &pipelineInfo, &count, nullptr));
  std::vector<VkPipelineExecutablePropertiesKHR> executables(count, {VK_STRUCTURE_TYPE_PIPELINE_EXECUTABLE_PROPERTIES_KHR});
  VK_TRY(getExecutables_(device_, &pipelineInfo, &count, executables.data()));
  std::vector<StageStatistics> rows;
  for (std::uint32_t index = 0; index < count; ++index) {
    StageStatistics row{{}, stageName(executables[index].stages), shaderNames(executables[index].stages, stages), {}, {}};
    ENGINE_TRY_ASSIGN(row.values, readValues(pipeline, index));
    rows.push_back(std::move(row));
  }
  return rows;
}

Expected<std::vector<std::pair<std::string, double>>> ShaderStatistics::readValues(VkPipeline pipeline,
                                                                                  std::uint32_t executable) const {
  VkPipelineExecutableInfoKHR info{VK_STRUCTURE_TYPE_PIPELINE_EXECUTABLE_INFO_KHR};
  info.pipeline = pipeline;
  info.executableIndex = executable;
  std::uint32_t count = 0;
  VK_TRY(getStatistics_(device_, &info, &count, nullptr));
  std::vector<VkPipelineExecutableStatisticKHR> statistics(count, {VK_STRUCTURE_TYPE_PIPELINE_EXECUTABLE_STATISTIC_KHR});
  VK_TRY(getStatistics_(device_, &info, &count, statistics.data()));
  std::vector<std::pair<std::string, double>> values;
  for (std::uint32_t i = 0; i < count; ++i) values.emplace_back(statistics[i].name, statisticValue(statistics[i]));
  return values;
}

void ShaderStatistics::store(const std::string& name, std::vector<StageStatistics> rows) {
  for (StageStatistics& row : rows) row.pipeline = name;
  const auto first = std::find_if(stages_.begin(), stages_.end(), [&](const StageStatistics& s) { return s.pipeline == name; });
  const auto at = stages_.erase(first, std::find_if(first, stages_.end(), [&](const StageStatistics& s) { return s.pipeline != name; }));
  stages_.insert(at, std::make_move_iterator(rows.begin()), std::make_move_iterator(rows.end()));
}

std::vector<StageStatistics> ShaderStatistics::stages() const {
  const std::lock_guard lock(mutex_);
  return stages_;
}

}  // namespace engine::gpu
