#pragma once
// Shader modules from build-time SPIR-V and graphics pipelines for dynamic rendering.
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include <vulkan/vulkan.h>

#include "engine/core/expected.h"

namespace engine::gpu {

class Context;

// Folder holding the compiled shaders: $HSDF_SHADER_DIR, else the build tree's shaders/ folder while
// it exists, else <program>/../<the installed shader folder> (an installed program, cmake --install;
// the folder, e.g. share/<package>/shaders, is the one cmake/HsdfInstall.cmake installs to).
std::filesystem::path shaderDirectory();
// A folder of a program's own SPIR-V (a project outside this repository compiles its shaders there,
// e.g. with the installed package's CMake function for shaders), searched before shaderDirectory(): a program's
// shader of the same name as one of the engine's is found first. Thread-safe; added once.
void addShaderDirectory(const std::filesystem::path& folder);
// The folders ShaderModule::load searches, in order: those added, then shaderDirectory().
std::vector<std::filesystem::path> shaderDirectories();

class ShaderModule {
 public:
  ShaderModule() = default;
  // Loads `<folder>/<name>.spv` from the first of shaderDirectories() that has it, e.g. name =
  // "mesh.vert"; the error names the folders searched when none has it.
  static Expected<ShaderModule> load(const Context& context, const std::string& name);
  ~ShaderModule();
  ShaderModule(ShaderModule&& other) noexcept;
  ShaderModule& operator=(ShaderModule&& other) noexcept;
  ShaderModule(const ShaderModule&) = delete;
  ShaderModule& operator=(const ShaderModule&) = delete;
  VkShaderModule handle() const { return module_; }

 private:
  void destroy() noexcept;
  const Context* context_ = nullptr;
  VkShaderModule module_ = VK_NULL_HANDLE;
};

struct VertexLayout {
  std::vector<VkVertexInputBindingDescription> bindings;
  std::vector<VkVertexInputAttributeDescription> attributes;
};

struct GraphicsPipelineDesc {
  std::string name = "pipeline";
  VkShaderModule vertex = VK_NULL_HANDLE;
  VkShaderModule fragment = VK_NULL_HANDLE;  // may be null: depth-only pipeline
  VertexLayout vertexLayout;
  VkPrimitiveTopology topology = VK_PRIMITIVE_TOPOLOGY_TRIANGLE_LIST;
  VkPolygonMode polygonMode = VK_POLYGON_MODE_FILL;
  VkCullModeFlags cullMode = VK_CULL_MODE_BACK_BIT;
  VkFrontFace frontFace = VK_FRONT_FACE_COUNTER_CLOCKWISE;
  bool depthTest = true;
  bool depthWrite = true;
  VkCompareOp depthCompare = VK_COMPARE_OP_GREATER;  // reverse-Z
  std::vector<VkFormat> colorFormats;
  VkFormat depthFormat = VK_FORMAT_UNDEFINED;
  bool alphaBlend = false;
  bool colorWrite = true;  // false: the colour attachments are kept as they are (e.g. a depth-only fix-up)
  std::uint32_t pushConstantBytes = 0;  // one range at offset 0, for the vertex and fragment stages
  std::vector<VkDescriptorSetLayout> setLayouts;
  // Besides viewport and scissor, which are always dynamic (e.g. VK_DYNAMIC_STATE_CULL_MODE).
  std::vector<VkDynamicState> extraDynamicStates;
};

class Pipeline {
 public:
  Pipeline() = default;
  static Expected<Pipeline> createGraphics(const Context& context, const GraphicsPipelineDesc& desc);
  // A compute pipeline without descriptor sets (buffers by device address, push constants only).
  static Expected<Pipeline> createCompute(const Context& context, const std::string& name, VkShaderModule shader,
                                          std::uint32_t pushConstantBytes);
  ~Pipeline();
  Pipeline(Pipeline&& other) noexcept;
  Pipeline& operator=(Pipeline&& other) noexcept;
  Pipeline(const Pipeline&) = delete;
  Pipeline& operator=(const Pipeline&) = delete;

  VkPipeline handle() const { return pipeline_; }
  VkPipelineLayout layout() const { return layout_; }
  explicit operator bool() const { return pipeline_ != VK_NULL_HANDLE; }

 private:
  void release();
  Status createLayout(const std::string& name, const VkPipelineLayoutCreateInfo& info);
  const Context* context_ = nullptr;
  VkPipeline pipeline_ = VK_NULL_HANDLE;
  VkPipelineLayout layout_ = VK_NULL_HANDLE;
};

}  // namespace engine::gpu
