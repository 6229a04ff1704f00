#include "engine/ui/ui_layer.h"

#include <algorithm>
#include <filesystem>
#include <string_view>

#include <GLFW/glfw3.h>
#include <imgui.h>
#include <imgui_impl_glfw.h>
#include <imgui_impl_vulkan.h>

#include "engine/core/files.h"
#include "engine/core/log.h"
#include "engine/gpu/context.h"
#include "engine/gpu/vk_check.h"
#include "engine/platform/window.h"

namespace engine::ui {
namespace {

void checkImGuiVk(VkResult result) {
  if (result != VK_SUCCESS) VK_CHECK(result);
}

// The UI's render pass: one colour attachment, loaded (the UI draws over the finished frame) and
// stored, in COLOR_ATTACHMENT_OPTIMAL throughout.
Status createOverlayPass(const gpu::Context& context, VkFormat colorFormat, VkRenderPass& renderPass) {
  VkAttachmentDescription attachment{};
  attachment.format = colorFormat;
  attachment.samples = VK_SAMPLE_COUNT_1_BIT;
  attachment.loadOp = VK_ATTACHMENT_LOAD_OP_LOAD;  // draw over the finished frame
  attachment.storeOp = VK_ATTACHMENT_STORE_OP_STORE;
  attachment.stencilLoadOp = VK_ATTACHMENT_LOAD_OP_DONT_CARE;
  attachment.stencilStoreOp = VK_ATTACHMENT_STORE_OP_DONT_CARE;
  attachment.initialLayout = VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL;
  attachment.finalLayout = VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL;
  VkAttachmentReference reference{0, VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL};
  VkSubpassDescription subpass{};
  subpass.pipelineBindPoint = VK_PIPELINE_BIND_POINT_GRAPHICS;
  subpass.colorAttachmentCount = 1;
  subpass.pColorAttachments = &reference;
  // The scene's colour writes must finish before the UI blends over them, and the UI's writes
  // before whatever follows (the renderer's transition to TRANSFER_SRC waits on this stage).
  VkSubpassDependency dependencies[2] = {};
  dependencies[0].srcSubpass = VK_SUBPASS_EXTERNAL;
  dependencies[0].dstSubpass = 0;
  dependencies[1].srcSubpass = 0;
  dependencies[1].dstSubpass = VK_SUBPASS_EXTERNAL;
  for (VkSubpassDependency& dependency : dependencies) {
    dependency.srcStageMask = VK_PIPELINE_STAGE_COLOR_ATTACHMENT_OUTPUT_BIT;
    dependency.dstStageMask = VK_PIPELINE_STAGE_COLOR_ATTACHMENT_OUTPUT_BIT;
    dependency.srcAccessMask = VK_ACCESS_COLOR_ATTACHMENT_WRITE_BIT;
    dependency.dstAccessMask = VK_ACCESS_COLOR_ATTACHMENT_READ_BIT | VK_ACCESS_COLOR_ATTACHMENT_WRITE_BIT;
  }
  VkRenderPassCreateInfo passInfo{VK_STRUCTURE_TYPE_RENDER_PASS_CREATE_INFO};
  passInfo.attachmentCount = 1;
  passInfo.pAttachments = &attachment;
  passInfo.subpassCount = 1;
  passInfo.pSubpasses = &subpass;
  passInfo.dependencyCount = 2;
  passInfo.pDependencies = dependencies;
  VK_TRY(vkCreateRenderPass(context.device(), &passInfo, nullptr, &renderPass));
  context.setName(renderPass, VK_OBJECT_TYPE_RENDER_PASS, "ui render pass");
  return {};
}

// The pool the ImGui Vulkan backend allocates its descriptor sets from (the font texture's).
Status createDescriptorPool(const gpu::Context& context, VkDescriptorPool& descriptorPool) {
  VkDescriptorPoolSize poolSize{VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, 16};
  VkDescriptorPoolCreateInfo poolInfo{VK_STRUCTURE_TYPE_DESCRIPTOR_POOL_CREATE_INFO};
  poolInfo.flags = VK_DESCRIPTOR_POOL_CREATE_FREE_DESCRIPTOR_SET_BIT;
  poolInfo.maxSets = 16;
  poolInfo.poolSizeCount = 1;
  poolInfo.pPoolSizes = &poolSize;
  VK_TRY(vkCreateDescriptorPool(context.device(), &poolInfo, nullptr, &descriptorPool));
  context.setName(descriptorPool, VK_OBJECT_TYPE_DESCRIPTOR_POOL, "ui descriptor pool");
  return {};
}

ImGui_ImplVulkan_InitInfo vulkanBackendInfo(const gpu::Context& context, VkDescriptorPool descriptorPool,
                                            std::uint32_t framesInFlight) {
  ImGui_ImplVulkan_InitInfo info{};
  info.Instance = context.instance();
  info.PhysicalDevice = context.physicalDevice();
  info.Device = context.device();
  info.QueueFamily = context.queueFamily();
  info.Queue = context.queue();
  info.DescriptorPool = descriptorPool;
  info.MinImageCount = 2;
  info.ImageCount = framesInFlight + 1;  // the backend rotates its vertex buffers per frame
  info.MSAASamples = VK_SAMPLE_COUNT_1_BIT;
  info.CheckVkResultFn = &checkImGuiVk;
  return info;
}

}  // namespace

Expected<std::unique_ptr<UiLayer>> UiLayer::create(const gpu::Context& context, VkFormat colorFormat,
                                                   std::uint32_t framesInFlight, platform::Window* window) {
  std::unique_ptr<UiLayer> layer(new UiLayer(context));
  ENGINE_TRY(layer->initialize(colorFormat, framesInFlight, window));
  return layer;
}

Status UiLayer::initialize(VkFormat colorFormat, std::uint32_t framesInFlight, platform::Window* window) {
  ENGINE_TRY(createOverlayPass(context_, colorFormat, renderPass_));
  ENGINE_TRY(createDescriptorPool(context_, descriptorPool_));
  IMGUI_CHECKVERSION();
  ImGui::CreateContext();
  ImGuiIO& io = ImGui::GetIO();
  io.IniFilename = nullptr;  // no imgui.ini next to the binary
  ImGui::StyleColorsDark();
  if (window) {
    if (!ImGui_ImplGlfw_InitForVulkan(window->handle(), true)) return makeError("ImGui GLFW backend failed to start");
    glfwBackend_ = true;
    window_ = window;
  }
  ImGui_ImplVulkan_InitInfo info = vulkanBackendInfo(context_, descriptorPool_, framesInFlight);
  if (!ImGui_ImplVulkan_Init(&info, renderPass_)) return makeError("ImGui Vulkan backend failed to start");
  vulkanBackend_ = true;
  context_.submitAndWait([](VkCommandBuffer cmd) { ImGui_ImplVulkan_CreateFontsTexture(cmd); });
  ImGui_ImplVulkan_DestroyFontUploadObjects();
  return {};
}

UiLayer::~UiLayer() {
  if (ImGui::GetCurrentContext()) saveLayout(true);  // as ImGui did at shutdown: a change of the last seconds too
  vkDeviceWaitIdle(context_.device());
  if (vulkanBackend_) ImGui_ImplVulkan_Shutdown();
  if (glfwBackend_) ImGui_ImplGlfw_Shutdown();
  if (ImGui::GetCurrentContext()) ImGui::DestroyContext();
  for (auto& [view, framebuffer] : framebuffers_) vkDestroyFramebuffer(context_.device(), framebuffer, nullptr);
  if (descriptorPool_) vkDestroyDescriptorPool(context_.device(), descriptorPool_, nullptr);
  if (renderPass_) vkDestroyRenderPass(context_.device(), renderPass_, nullptr);
}

void UiLayer::addPanel(std::string name, std::function<void()> draw) {
  panels_.push_back({std::move(name), std::move(draw)});
}

void UiLayer::setIniFile(const std::string& file) {
  iniFile_ = file;
  layoutWriteFailed_ = false;
  // ImGui saves nothing itself (no IniFilename): it raises WantSaveIniSettings, and saveLayout writes.
  ImGui::GetIO().IniFilename = nullptr;
  if (iniFile_.empty()) return;
  // Read by the engine's reader, not ImGui's: ImGui's took a folder's size as 2^63 bytes and asked
  // malloc for them (AddressSanitizer stopped there; without it the layout was dropped unsaid).
  if (std::filesystem::exists(iniFile_)) {
    if (const Expected<std::string> text = readTextFile(iniFile_))
      ImGui::LoadIniSettingsFromMemory(text->data(), text->size());
    else
      log::warn("the window layout was not loaded: {}", text.error().message);
  }
  if (const Status writable = checkWritable(iniFile_); !writable) {
    log::warn("the window layout will not be saved: {}", writable.error().message);
    layoutWriteFailed_ = true;
  }
}

// Writes ImGui's layout when it asks to (a few seconds after a change), or whatever it is (shutdown).
void UiLayer::saveLayout(bool evenUnchanged) {
  ImGuiIO& io = ImGui::GetIO();
  if (iniFile_.empty() || (!io.WantSaveIniSettings && !evenUnchanged)) return;
  std::size_t size = 0;
  const char* text = ImGui::SaveIniSettingsToMemory(&size);
  io.WantSaveIniSettings = false;
  const Status written = writeTextFile(iniFile_, std::string_view(text, size));
  if (!written && !layoutWriteFailed_) log::warn("the window layout was not saved: {}", written.error().message);
  layoutWriteFailed_ = !written;
}

void UiLayer::addFeaturePanels(const render::Renderer& renderer) {
  for (const auto& feature : renderer.features()) {
    render::RenderFeature* f = feature.get();
    addPanel(std::string(f->name()), [f] { f->drawUi(); });
  }
}

void UiLayer::buildFrame(VkExtent2D extent, float deltaSeconds) {
  ImGuiIO& io = ImGui::GetIO();
  ImGui_ImplVulkan_NewFrame();
  if (glfwBackend_) {
    showKeysToImGui();
    ImGui_ImplGlfw_NewFrame();
  } else {
    io.DisplaySize = ImVec2(float(extent.width), float(extent.height));
    io.DeltaTime = deltaSeconds > 0.0f ? deltaSeconds : 1.0f / 60.0f;
  }
  ImGui::NewFrame();
  ImGui::SetNextWindowPos(ImVec2(10, 10), ImGuiCond_FirstUseEver);
  // A fixed size, not auto-fit: ImGui hides an auto-fitting window in its first frame, and a
  // one-frame headless screenshot would show no panel.
  ImGui::SetNextWindowSize(ImVec2(420.0f, std::max(120.0f, float(extent.height) - 20.0f)), ImGuiCond_FirstUseEver);
  const bool open = ImGui::Begin(windowTitle_.c_str());
  keepTitleBarReachable(io.DisplaySize);
  if (open) {
    for (Panel& panel : panels_) {
      ImGui::PushID(panel.name.c_str());
      panel.draw();
      ImGui::PopID();
    }
  }
  ImGui::End();
  ImGui::Render();
  saveLayout(false);
  frameBuilt_ = true;
}

// Inside the current window: a display made tiny (a window resized to 10x10) makes ImGui push the
// window up and left until a few pixels of it stay inside; made large again, the window stayed
// there with its title bar above the display, where it cannot be dragged or collapsed. The title
// bar's left end (the collapse arrow) is put back inside; a window dragged past the right or
// bottom edge keeps 40 pixels of its title bar visible.
void UiLayer::keepTitleBarReachable(const ImVec2& display) {
  constexpr float kVisible = 40.0f;
  const ImVec2 pos = ImGui::GetWindowPos();
  const ImVec2 kept(std::clamp(pos.x, 0.0f, std::max(0.0f, display.x - kVisible)),
                    std::clamp(pos.y, 0.0f, std::max(0.0f, display.y - ImGui::GetFrameHeight())));
  if (kept.x != pos.x || kept.y != pos.y) ImGui::SetWindowPos(kept);
}

// Dear ImGui 1.86 (Debian 12's) keeps keys as levels: its GLFW backend writes io.KeysDown at each
// key event and NewFrame() compares them with the last frame's. A key pressed and released between
// two frames (a quick tap while a frame takes 50-500 ms) is up again when NewFrame() looks, so the
// press is lost: Return tapped in a slider's text field left it in edit mode. (Characters are not
// affected: they are queued. Mouse clicks neither: the backend keeps a just-pressed flag. ImGui
// 1.87 queues key events and needs none of this.) So the levels ImGui reads are replaced by the
// window's: every press since the last frame shows down for this frame, a release that came in
// the same frame as its press is delivered one frame late (PolledKeyLevels), and the modifiers
// follow the same levels.
void UiLayer::showKeysToImGui() {
#if IMGUI_VERSION_NUM < 18700
  if (!window_) return;
  imguiKeys_.update(window_->input());
  ImGuiIO& io = ImGui::GetIO();
  constexpr int kKeys = std::min(int(sizeof(ImGuiIO::KeysDown) / sizeof(bool)), platform::InputState::kKeyCount);
  for (int key = 0; key < kKeys; ++key) io.KeysDown[key] = imguiKeys_.down(key);
  auto down = [&](int a, int b) { return imguiKeys_.down(a) || imguiKeys_.down(b); };
  io.KeyCtrl = down(GLFW_KEY_LEFT_CONTROL, GLFW_KEY_RIGHT_CONTROL);
  io.KeyShift = down(GLFW_KEY_LEFT_SHIFT, GLFW_KEY_RIGHT_SHIFT);
  io.KeyAlt = down(GLFW_KEY_LEFT_ALT, GLFW_KEY_RIGHT_ALT);
  io.KeySuper = down(GLFW_KEY_LEFT_SUPER, GLFW_KEY_RIGHT_SUPER);
#endif
}

bool UiLayer::wantsMouse() const { return ImGui::GetIO().WantCaptureMouse; }
bool UiLayer::wantsKeyboard() const { return ImGui::GetIO().WantCaptureKeyboard; }

VkFramebuffer UiLayer::framebufferFor(const gpu::Image& color) {
  if (auto it = framebuffers_.find(color.view()); it != framebuffers_.end()) return it->second;
  // The target was recreated (resize): the cached framebuffers point at destroyed views.
  for (auto& [view, framebuffer] : framebuffers_) vkDestroyFramebuffer(context_.device(), framebuffer, nullptr);
  framebuffers_.clear();
  VkImageView view = color.view();
  VkFramebufferCreateInfo info{VK_STRUCTURE_TYPE_FRAMEBUFFER_CREATE_INFO};
  info.renderPass = renderPass_;
  info.attachmentCount = 1;
  info.pAttachments = &view;
  info.width = color.extent().width;
  info.height = color.extent().height;
  info.layers = 1;
  VkFramebuffer framebuffer = VK_NULL_HANDLE;
  VK_CHECK(vkCreateFramebuffer(context_.device(), &info, nullptr, &framebuffer));
  context_.setName(framebuffer, VK_OBJECT_TYPE_FRAMEBUFFER, "ui framebuffer");
  framebuffers_.emplace(view, framebuffer);
  return framebuffer;
}

void UiLayer::record(VkCommandBuffer cmd, const gpu::Image& color, std::uint32_t /*frameSlot*/) {
  if (!frameBuilt_) return;
  frameBuilt_ = false;
  VkRenderPassBeginInfo begin{VK_STRUCTURE_TYPE_RENDER_PASS_BEGIN_INFO};
  begin.renderPass = renderPass_;
  begin.framebuffer = framebufferFor(color);
  begin.renderArea = {{0, 0}, {color.extent().width, color.extent().height}};
  vkCmdBeginRenderPass(cmd, &begin, VK_SUBPASS_CONTENTS_INLINE);
  ImGui_ImplVulkan_RenderDrawData(ImGui::GetDrawData(), cmd);
  vkCmdEndRenderPass(cmd);
}

}  // namespace engine::ui
