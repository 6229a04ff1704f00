#include "engine/gpu/pipeline.h"

#include <algorithm>
#include <cstdlib>
#include <mutex>
#include <utility>

#include "engine/core/files.h"
#include "engine/gpu/context.h"
#include "engine/gpu/shader_statistics.h"
#include "engine/gpu/spirv_check.h"
#include "engine/gpu/vk_check.h"

#ifndef HSDF_SHADER_DIR
#error "HSDF_SHADER_DIR must be defined by the build"
#endif
#ifndef HSDF_INSTALLED_SHADER_DIR
#error "HSDF_INSTALLED_SHADER_DIR must be defined by the build (cmake/HsdfInstall.cmake)"
#endif

namespace engine::gpu {

namespace {

// Where an installed program's SPIR-V lies (cmake --install: bin/ and the package's shader folder
// below the prefix, named by the build that installs it rather than by the engine).
std::filesystem::path installedShaderDirectory() {
  std::error_code ec;
  const std::filesystem::path exe = std::filesystem::read_symlink("/proc/self/exe", ec);
  if (ec) return {};
  return exe.parent_path().parent_path() / HSDF_INSTALLED_SHADER_DIR;
}

std::mutex& addedShaderDirectoriesMutex() {
  static std::mutex mutex;
  return mutex;
}
std::vector<std::filesystem::path>& addedShaderDirectories() {
  static std::vector<std::filesystem::path> folders;
  return folders;
}

// Where `name` is: the first folder that has the file, else the last folder's (whose read error
// then names a file that is not there).
std::filesystem::path findShader(const std::vector<std::filesystem::path>& folders, const std::string& file) {
  std::error_code ec;
  for (const std::filesystem::path& folder : folders)
    if (std::filesystem::is_regular_file(folder / file, ec)) return folder / file;
  return folders.back() / file;
}

// A pipeline layout's create info: one push constant range at offset 0 (none for 0 bytes) and the
// set layouts; the layout and a statistics device's copy of it are made from the same info.
struct LayoutInfo {
  LayoutInfo(VkShaderStageFlags pushStages, std::uint32_t pushConstantBytes,
             const std::vector<VkDescriptorSetLayout>& sets)
      : setLayouts(sets), pushRange{pushStages, 0, pushConstantBytes} {
    info.setLayoutCount = static_cast<std::uint32_t>(setLayouts.size());
    info.pSetLayouts = setLayouts.data();
    info.pushConstantRangeCount = pushConstantBytes ? 1 : 0;
    info.pPushConstantRanges = &pushRange;
  }
  LayoutInfo(const LayoutInfo&) = delete;  // info points into it
  LayoutInfo& operator=(const LayoutInfo&) = delete;
  std::vector<VkDescriptorSetLayout> setLayouts;
  VkPushConstantRange pushRange;
  VkPipelineLayoutCreateInfo info{VK_STRUCTURE_TYPE_PIPELINE_LAYOUT_CREATE_INFO};
};

// A graphics pipeline's create info, each state from its description: like LayoutInfo, `info`
// points into the struct (a statistics device compiles the same info again).
class GraphicsInfo {
 public:
  GraphicsInfo(const GraphicsPipelineDesc& desc, VkPipelineLayout layout) {
    describeShaders(desc);
    describeGeometry(desc);
    describeAttachments(desc);
    describeDynamicStates(desc);
    link(layout);
  }
  GraphicsInfo(const GraphicsInfo&) = delete;
  GraphicsInfo& operator=(const GraphicsInfo&) = delete;
  VkGraphicsPipelineCreateInfo info{VK_STRUCTURE_TYPE_GRAPHICS_PIPELINE_CREATE_INFO};

 private:
  // The vertex stage, and the fragment stage where there is one (a depth-only pipeline has none).
  void describeShaders(const GraphicsPipelineDesc& desc) {
    VkPipelineShaderStageCreateInfo stage{VK_STRUCTURE_TYPE_PIPELINE_SHADER_STAGE_CREATE_INFO};
    stage.pName = "main";
    stage.stage = VK_SHADER_STAGE_VERTEX_BIT;
    stage.module = desc.vertex;
    stages_.push_back(stage);
    if (desc.fragment) {
      stage.stage = VK_SHADER_STAGE_FRAGMENT_BIT;
      stage.module = desc.fragment;
      stages_.push_back(stage);
    }
  }

  // Vertex input, assembly, one dynamic viewport, rasterization, one sample and the depth test.
  void describeGeometry(const GraphicsPipelineDesc& desc) {
    vertexInput_.vertexBindingDescriptionCount = static_cast<std::uint32_t>(desc.vertexLayout.bindings.size());
    vertexInput_.pVertexBindingDescriptions = desc.vertexLayout.bindings.data();
    vertexInput_.vertexAttributeDescriptionCount = static_cast<std::uint32_t>(desc.vertexLayout.attributes.size());
    vertexInput_.pVertexAttributeDescriptions = desc.vertexLayout.attributes.data();
    inputAssembly_.topology = desc.topology;
    viewport_.viewportCount = 1;
    viewport_.scissorCount = 1;
    raster_.polygonMode = desc.polygonMode;
    raster_.cullMode = desc.cullMode;
    raster_.frontFace = desc.frontFace;
    raster_.lineWidth = 1.0f;
    multisample_.rasterizationSamples = VK_SAMPLE_COUNT_1_BIT;
    depth_.depthTestEnable = desc.depthTest;
    depth_.depthWriteEnable = desc.depthWrite;
    depth_.depthCompareOp = desc.depthCompare;
  }

  // Every colour attachment alike (written or kept, blended by alpha or not), and the formats
  // dynamic rendering draws into.
  void describeAttachments(const GraphicsPipelineDesc& desc) {
    blends_.resize(desc.colorFormats.size());
    for (auto& blend : blends_) {
      blend.colorWriteMask = desc.colorWrite ? VK_COLOR_COMPONENT_R_BIT | VK_COLOR_COMPONENT_G_BIT |
                                                   VK_COLOR_COMPONENT_B_BIT | VK_COLOR_COMPONENT_A_BIT
                                             : 0;
      if (desc.alphaBlend) {
        blend.blendEnable = VK_TRUE;
        blend.srcColorBlendFactor = VK_BLEND_FACTOR_SRC_ALPHA;
        blend.dstColorBlendFactor = VK_BLEND_FACTOR_ONE_MINUS_SRC_ALPHA;
        blend.colorBlendOp = VK_BLEND_OP_ADD;
        blend.srcAlphaBlendFactor = VK_BLEND_FACTOR_ONE;
        blend.dstAlphaBlendFactor = VK_BLEND_FACTOR_ONE_MINUS_SRC_ALPHA;
        blend.alphaBlendOp = VK_BLEND_OP_ADD;
      }
    }
    blend_.attachmentCount = static_cast<std::uint32_t>(blends_.size());
    blend_.pAttachments = blends_.data();
    rendering_.colorAttachmentCount = static_cast<std::uint32_t>(desc.colorFormats.size());
    rendering_.pColorAttachmentFormats = desc.colorFormats.data();
    rendering_.depthAttachmentFormat = desc.depthFormat;
  }

  void describeDynamicStates(const GraphicsPipelineDesc& desc) {
    dynamicStates_ = {VK_DYNAMIC_STATE_VIEWPORT, VK_DYNAMIC_STATE_SCISSOR};
    dynamicStates_.insert(dynamicStates_.end(), desc.extraDynamicStates.begin(), desc.extraDynamicStates.end());
    dynamic_.dynamicStateCount = static_cast<std::uint32_t>(dynamicStates_.size());
    dynamic_.pDynamicStates = dynamicStates_.data();
  }

  void link(VkPipelineLayout layout) {
    info.pNext = &rendering_;
    info.stageCount = static_cast<std::uint32_t>(stages_.size());
    info.pStages = stages_.data();
    info.pVertexInputState = &vertexInput_;
    info.pInputAssemblyState = &inputAssembly_;
    info.pViewportState = &viewport_;
    info.pRasterizationState = &raster_;
    info.pMultisampleState = &multisample_;
    info.pDepthStencilState = &depth_;
    info.pColorBlendState = &blend_;
    info.pDynamicState = &dynamic_;
    info.layout = layout;
  }

  std::vector<VkPipelineShaderStageCreateInfo> stages_;
  VkPipelineVertexInputStateCreateInfo vertexInput_{VK_STRUCTURE_TYPE_PIPELINE_VERTEX_INPUT_STATE_CREATE_INFO};
  VkPipelineInputAssemblyStateCreateInfo inputAssembly_{VK_STRUCTURE_TYPE_PIPELINE_INPUT_ASSEMBLY_STATE_CREATE_INFO};
  VkPipelineViewportStateCreateInfo viewport_{VK_STRUCTURE_TYPE_PIPELINE_VIEWPORT_STATE_CREATE_INFO};
  VkPipelineRasterizationStateCreateInfo raster_{VK_STRUCTURE_TYPE_PIPELINE_RASTERIZATION_STATE_CREATE_INFO};
  VkPipelineMultisampleStateCreateInfo multisample_{VK_STRUCTURE_TYPE_PIPELINE_MULTISAMPLE_STATE_CREATE_INFO};
  VkPipelineDepthStencilStateCreateInfo depth_{VK_STRUCTURE_TYPE_PIPELINE_DEPTH_STENCIL_STATE_CREATE_INFO};
  std::vector<VkPipelineColorBlendAttachmentState> blends_;
  VkPipelineColorBlendStateCreateInfo blend_{VK_STRUCTURE_TYPE_PIPELINE_COLOR_BLEND_STATE_CREATE_INFO};
  std::vector<VkDynamicState> dynamicStates_;
  VkPipelineDynamicStateCreateInfo dynamic_{VK_STRUCTURE_TYPE_PIPELINE_DYNAMIC_STATE_CREATE_INFO};
  VkPipelineRenderingCreateInfo rendering_{VK_STRUCTURE_TYPE_PIPELINE_RENDERING_CREATE_INFO};
};

}  // namespace

void addShaderDirectory(const std::filesystem::path& folder) {
  const std::lock_guard lock(addedShaderDirectoriesMutex());
  std::vector<std::filesystem::path>& folders = addedShaderDirectories();
  if (std::find(folders.begin(), folders.end(), folder) == folders.end()) folders.push_back(folder);
}

std::vector<std::filesystem::path> shaderDirectories() {
  std::vector<std::filesystem::path> folders;
  {
    const std::lock_guard lock(addedShaderDirectoriesMutex());
    folders = addedShaderDirectories();
  }
  folders.push_back(shaderDirectory());
  return folders;
}

std::filesystem::path shaderDirectory() {
  if (const char* dir = std::getenv("HSDF_SHADER_DIR"); dir && *dir) return dir;  // empty: unset, not the cwd
  // The build tree the program was compiled in, while it exists; else the installed copy.
  std::error_code ec;
  if (std::filesystem::is_directory(HSDF_SHADER_DIR, ec)) return HSDF_SHADER_DIR;
  const std::filesystem::path installed = installedShaderDirectory();
  if (!installed.empty() && std::filesystem::is_directory(installed, ec)) return installed;
  return HSDF_SHADER_DIR;  // missing: ShaderModule::load names the file it could not read
}

Expected<ShaderModule> ShaderModule::load(const Context& context, const std::string& name) {
  const std::vector<std::filesystem::path> folders = shaderDirectories();
  const std::filesystem::path path = findShader(folders, name + ".spv");
  auto bytes = readBinaryFile(path, 64u << 20);
  if (!bytes) {  // say where the folders came from: a stale HSDF_SHADER_DIR is the usual cause
    std::string searched;
    for (std::size_t i = 0; i + 1 < folders.size(); ++i) searched += folders[i].string() + ", ";
    const char* env = std::getenv("HSDF_SHADER_DIR");
    const std::string where = folders.size() > 1 || (env && *env)
                                  ? " (searched " + searched + (env && *env ? "HSDF_SHADER_DIR's " : "") +
                                        folders.back().string() + ")"
                                  : "";
    return bytes.error().withContext("shader " + name + where);
  }
  // Checked here, not left to the driver: invalid SPIR-V is undefined behaviour in
  // vkCreateShaderModule (a reload of a broken or half-written file must fail cleanly, old
  // pipelines kept).
  if (Status valid = checkSpirv(*bytes); !valid) return makeError("shader " + path.string() + ": " + valid.error().message);
  VkShaderModuleCreateInfo info{VK_STRUCTURE_TYPE_SHADER_MODULE_CREATE_INFO};
  info.codeSize = bytes->size();
  info.pCode = reinterpret_cast<const std::uint32_t*>(bytes->data());
  ShaderModule module;
  module.context_ = &context;
  VK_TRY(vkCreateShaderModule(context.device(), &info, nullptr, &module.module_));
  context.setName(module.module_, VK_OBJECT_TYPE_SHADER_MODULE, name);
  // The statistics device compiles the pipelines again: it gets the SPIR-V while the module lives.
  if (ShaderStatistics* statistics = context.shaderStatistics()) ENGINE_TRY(statistics->addShader(module.module_, name, *bytes));
  return module;
}

ShaderModule::~ShaderModule() { destroy(); }

void ShaderModule::destroy() noexcept {
  if (!module_) return;
  if (ShaderStatistics* statistics = context_->shaderStatistics()) statistics->removeShader(module_);
  vkDestroyShaderModule(context_->device(), module_, nullptr);
  module_ = VK_NULL_HANDLE;
}

ShaderModule::ShaderModule(ShaderModule&& other) noexcept { *this = std::move(other); }

ShaderModule& ShaderModule::operator=(ShaderModule&& other) noexcept {
  if (this != &other) {
    destroy();
    context_ = std::exchange(other.context_, nullptr);
    module_ = std::exchange(other.module_, VK_NULL_HANDLE);
  }
  return *this;
}

Status Pipeline::createLayout(const std::string& name, const VkPipelineLayoutCreateInfo& info) {
  VK_TRY(vkCreatePipelineLayout(context_->device(), &info, nullptr, &layout_));
  context_->setName(layout_, VK_OBJECT_TYPE_PIPELINE_LAYOUT, name + " layout");
  return {};
}

Expected<Pipeline> Pipeline::createCompute(const Context& context, const std::string& name, VkShaderModule shader,
                                           std::uint32_t pushConstantBytes) {
  Pipeline result;
  result.context_ = &context;
  const LayoutInfo layout(VK_SHADER_STAGE_COMPUTE_BIT, pushConstantBytes, {});
  ENGINE_TRY(result.createLayout(name, layout.info));
  ShaderStatistics* statistics = context.shaderStatistics();
  VkComputePipelineCreateInfo info{VK_STRUCTURE_TYPE_COMPUTE_PIPELINE_CREATE_INFO};
  info.stage = {VK_STRUCTURE_TYPE_PIPELINE_SHADER_STAGE_CREATE_INFO};
  info.stage.stage = VK_SHADER_STAGE_COMPUTE_BIT;
  info.stage.module = shader;
  info.stage.pName = "main";
  info.layout = result.layout_;
  if (statistics) info.flags |= statistics->pipelineFlags();
  VK_TRY(vkCreateComputePipelines(context.device(), context.pipelineCache().handle(), 1, &info, nullptr, &result.pipeline_));
  context.setName(result.pipeline_, VK_OBJECT_TYPE_PIPELINE, name);
  if (statistics) statistics->record(name, info, layout.info, result.pipeline_);
  return result;
}

Expected<Pipeline> Pipeline::createGraphics(const Context& context, const GraphicsPipelineDesc& desc) {
  Pipeline result;
  result.context_ = &context;
  const LayoutInfo layout(VK_SHADER_STAGE_VERTEX_BIT | VK_SHADER_STAGE_FRAGMENT_BIT, desc.pushConstantBytes,
                          desc.setLayouts);
  ENGINE_TRY(result.createLayout(desc.name, layout.info));
  GraphicsInfo graphics(desc, result.layout_);
  VkGraphicsPipelineCreateInfo& info = graphics.info;
  ShaderStatistics* statistics = context.shaderStatistics();
  if (statistics) info.flags |= statistics->pipelineFlags();
  VK_TRY(vkCreateGraphicsPipelines(context.device(), context.pipelineCache().handle(), 1, &info, nullptr, &result.pipeline_));
  context.setName(result.pipeline_, VK_OBJECT_TYPE_PIPELINE, desc.name);
  if (statistics) statistics->record(desc.name, info, layout.info, result.pipeline_);
  return result;
}

Pipeline::~Pipeline() { release(); }

Pipeline::Pipeline(Pipeline&& other) noexcept { *this = std::move(other); }

Pipeline& Pipeline::operator=(Pipeline&& other) noexcept {
  if (this != &other) {
    release();
    context_ = std::exchange(other.context_, nullptr);
    pipeline_ = std::exchange(other.pipeline_, VK_NULL_HANDLE);
    layout_ = std::exchange(other.layout_, VK_NULL_HANDLE);
  }
  return *this;
}

void Pipeline::release() {
  if (!context_) return;
  if (pipeline_) vkDestroyPipeline(context_->device(), pipeline_, nullptr);
  if (layout_) vkDestroyPipelineLayout(context_->device(), layout_, nullptr);
  pipeline_ = VK_NULL_HANDLE;
  layout_ = VK_NULL_HANDLE;
}

}  // namespace engine::gpu
