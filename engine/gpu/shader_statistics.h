#pragma once
// The shader compiler's statistics of every pipeline the engine builds (VGPRs, SGPRs, spills,
// scratch, instructions, occupancy, ... as the driver names them), per pipeline and stage, through
// VK_KHR_pipeline_executable_properties. Opt-in (ContextDesc::shaderStatistics), on one of two
// targets:
// - Native: the device the program renders on, where it has the extension: its own pipelines are
//   created with VK_PIPELINE_CREATE_CAPTURE_STATISTICS_BIT_KHR and read.
// - Device: a second VkDevice of the same instance that only compiles, e.g. Mesa RADV's null
//   device for an AMD GPU family (RADV_FORCE_FAMILY=navi10: "Null hardware (RADV NAVI10)"). Every
//   pipeline is compiled there again from the same SPIR-V, set layouts and state, and destroyed once
//   its statistics are read; the rendering device draws as it always does.
// They are what the compiler made of a shader for one GPU, not timings.
#include <cstddef>
#include <cstdint>
#include <memory>
#include <mutex>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <unordered_map>
#include <utility>
#include <vector>

#include <vulkan/vulkan.h>

#include "engine/core/expected.h"

namespace engine::gpu {

enum class StatisticsTarget { Off, Native, Device };

struct ShaderStatisticsDesc {
  StatisticsTarget target = StatisticsTarget::Off;
  // Device: a part of the statistics device's name, e.g. "NAVI10" (case counts).
  std::string deviceName;
};

// One stage of one pipeline, as its statistics device compiled it.
struct StageStatistics {
  std::string pipeline;  // the name the pipeline was created with
  std::string stage;     // "vertex", "fragment", "compute"
  std::string shader;    // the SPIR-V the stage came from, as ShaderModule::load named it
  std::vector<std::pair<std::string, double>> values;  // the driver's names and values, in its order
  std::string error;     // why the statistics device could not compile the pipeline (then no values)
  // The value of the statistic named `name` ("VGPRs"), if the driver reported one.
  std::optional<double> value(std::string_view name) const;
};

// Whether a device of this name only compiles and cannot run anything (RADV's null device: a
// submission crashes), so that it is never chosen to render.
bool isNullDevice(std::string_view deviceName);

class ShaderStatistics {
 public:
  // Native: `device` renders and was created with the extension and its feature on.
  static std::unique_ptr<ShaderStatistics> createNative(VkDevice device, std::string deviceName);
  // Device: the first physical device of `instance` whose name holds `desc.deviceName` gets a
  // device of its own; the error names the devices there are when none does.
  static Expected<std::unique_ptr<ShaderStatistics>> createOnDevice(VkInstance instance,
                                                                    const ShaderStatisticsDesc& desc);
  ~ShaderStatistics();
  ShaderStatistics(const ShaderStatistics&) = delete;
  ShaderStatistics& operator=(const ShaderStatistics&) = delete;

  StatisticsTarget target() const { return target_; }
  // The device the statistics come from.
  const std::string& deviceName() const { return deviceName_; }

  // What the statistics device needs to compile what the rendering device compiles: each shader
  // module (by name, with its SPIR-V) and each descriptor set layout, while it lives.
  Status addShader(VkShaderModule module, const std::string& name, std::span<const std::uint8_t> spirv);
  void removeShader(VkShaderModule module);
  Status addSetLayout(VkDescriptorSetLayout layout, const VkDescriptorSetLayoutCreateInfo& info);
  void removeSetLayout(VkDescriptorSetLayout layout);

  // Flags for the rendering device's pipelines (Native: capture statistics there).
  VkPipelineCreateFlags pipelineFlags() const;
  // Records the statistics of `pipeline`, just created on the rendering device from `info` (its
  // layout made from `layout`) under `name`; a pipeline of the same name recorded before is
  // replaced (shader reloads). What the statistics device cannot compile is recorded as an error.
  void record(const std::string& name, const VkGraphicsPipelineCreateInfo& info,
              const VkPipelineLayoutCreateInfo& layout, VkPipeline pipeline);
  void record(const std::string& name, const VkComputePipelineCreateInfo& info,
              const VkPipelineLayoutCreateInfo& layout, VkPipeline pipeline);

  // Every stage recorded, in the order the pipelines were first created.
  std::vector<StageStatistics> stages() const;

 private:
  ShaderStatistics() = default;
  struct Shader {
    std::string name;
    VkShaderModule copy = VK_NULL_HANDLE;  // Device: the module on the statistics device
  };
  Status createDevice(VkPhysicalDevice physicalDevice);
  // Reading (the caller holds mutex_): a pipeline of the reading device, or a copy compiled there.
  std::vector<StageStatistics> readNative(VkPipeline pipeline, std::span<const VkPipelineShaderStageCreateInfo> stages) const;
  template <class Info>
  std::vector<StageStatistics> readCopy(const Info& info, const VkPipelineLayoutCreateInfo& layout,
                                        std::span<const VkPipelineShaderStageCreateInfo> stages) const;
  Expected<std::vector<StageStatistics>> readStages(VkPipeline pipeline,
                                                    std::span<const VkPipelineShaderStageCreateInfo> stages) const;
  Expected<std::vector<std::pair<std::string, double>>> readValues(VkPipeline pipeline, std::uint32_t executable) const;
  std::vector<StageStatistics> failedStages(std::span<const VkPipelineShaderStageCreateInfo> stages,
                                            const std::string& why) const;
  std::string shaderNames(VkShaderStageFlags executableStages, std::span<const VkPipelineShaderStageCreateInfo> stages) const;
  Expected<VkPipelineLayout> copyLayout(const VkPipelineLayoutCreateInfo& info) const;
  Expected<VkShaderModule> copiedModule(VkShaderModule module) const;
  Expected<VkPipeline> compileCopy(VkGraphicsPipelineCreateInfo info, VkPipelineLayout layout) const;
  Expected<VkPipeline> compileCopy(VkComputePipelineCreateInfo info, VkPipelineLayout layout) const;
  void store(const std::string& name, std::vector<StageStatistics> rows);

  StatisticsTarget target_ = StatisticsTarget::Off;
  std::string deviceName_;
  VkDevice device_ = VK_NULL_HANDLE;  // where statistics are read
  bool ownsDevice_ = false;
  PFN_vkGetPipelineExecutablePropertiesKHR getExecutables_ = nullptr;
  PFN_vkGetPipelineExecutableStatisticsKHR getStatistics_ = nullptr;
  mutable std::mutex mutex_;
  std::unordered_map<VkShaderModule, Shader> shaders_;
  std::unordered_map<VkDescriptorSetLayout, VkDescriptorSetLayout> setLayouts_;  // rendering -> copy
  std::vector<StageStatistics> stages_;
};

}  // namespace engine::gpu
