#pragma once
// Dear ImGui inside the engine: the UI pass (a classic VkRenderPass, since Debian's ImGui 1.86
// Vulkan backend has no dynamic-rendering path) and the panel registry that render features and
// samples add their tuning panels to. Works with a window (GLFW input) and headless (no input,
// for screenshots that show the panels).
#include <functional>
#include <memory>
#include <string>
#include <unordered_map>
#include <utility>
#include <vector>

#include "engine/core/expected.h"
#include "engine/platform/input_events.h"
#include "engine/render/renderer.h"

struct ImVec2;

namespace engine::platform {
class Window;
}

namespace engine::ui {

class UiLayer final : public render::OverlayPass {
 public:
  static Expected<std::unique_ptr<UiLayer>> create(const gpu::Context& context, VkFormat colorFormat,
                                                   std::uint32_t framesInFlight, platform::Window* window);
  ~UiLayer() override;
  UiLayer(const UiLayer&) = delete;
  UiLayer& operator=(const UiLayer&) = delete;

  // Panels are drawn every frame in registration order, each inside the one main window.
  void addPanel(std::string name, std::function<void()> draw);
  // The main window's title (the program names it; ImGui also keys the window's saved layout on it).
  void setWindowTitle(std::string title) { windowTitle_ = std::move(title); }
  // ImGui's window layout: loaded from `file` now (when it exists) and saved to it while the UI
  // runs (a few seconds after a change) and at shutdown, through engine::writeBinaryFile: a file
  // that cannot be written is said once, as a warning naming it and why (ImGui's own writer
  // dropped the error). Empty: not kept (the default).
  void setIniFile(const std::string& file);

  // Adds every render feature's drawUi() as a panel.
  void addFeaturePanels(const render::Renderer& renderer);

  // Builds this frame's UI (call once per frame before Renderer::renderFrame, after the window's
  // pollEvents: the key presses ImGui is shown are that poll's).
  void buildFrame(VkExtent2D extent, float deltaSeconds);
  // True when ImGui wants the mouse/keyboard (camera controllers should ignore them).
  bool wantsMouse() const;
  bool wantsKeyboard() const;

  void record(VkCommandBuffer cmd, const gpu::Image& color, std::uint32_t frameSlot) override;

 private:
  UiLayer(const gpu::Context& context) : context_(context) {}
  Status initialize(VkFormat colorFormat, std::uint32_t framesInFlight, platform::Window* window);
  VkFramebuffer framebufferFor(const gpu::Image& color);
  void showKeysToImGui();
  static void keepTitleBarReachable(const ImVec2& display);
  void saveLayout(bool evenUnchanged);

  struct Panel {
    std::string name;
    std::function<void()> draw;
  };

  const gpu::Context& context_;
  VkRenderPass renderPass_ = VK_NULL_HANDLE;
  VkDescriptorPool descriptorPool_ = VK_NULL_HANDLE;
  std::unordered_map<VkImageView, VkFramebuffer> framebuffers_;
  std::vector<Panel> panels_;
  std::string iniFile_;
  bool layoutWriteFailed_ = false;  // said once
  std::string windowTitle_ = "engine";
  platform::Window* window_ = nullptr;  // null headless
  // ImGui 1.86 reads keys as levels once a frame: a tap within one frame is stretched over a frame
  // (buildFrame).
  platform::PolledKeyLevels imguiKeys_;
  bool glfwBackend_ = false;
  bool vulkanBackend_ = false;
  bool frameBuilt_ = false;
};

}  // namespace engine::ui
