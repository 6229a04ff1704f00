// The engine's ImGui layer, headless (no window, as the runner's --headless --ui screenshots): its
// panels draw in registration order over the finished frame, inside the one main window, and
// touch nothing else.
#include <gtest/gtest.h>

#include <imgui.h>
#include <imgui_internal.h>  // ImGui::MarkIniSettingsDirty: a layout change without a mouse
#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "engine/core/files.h"
#include "engine/core/log.h"
#include "engine/render/camera_view.h"
#include "engine/ui/ui_layer.h"
#include "gpu_test_support.h"
#include "log_capture.h"

namespace {

using engine::render::CameraView;

class UiLayerTest : public gputest::GpuTest {
 protected:
  static constexpr std::uint32_t kWidth = 256, kHeight = 192;
  // The main window's rectangle: UiLayer::buildFrame places it at (10, 10), 420 wide, the frame's
  // height less 20 tall (clipped by the frame).
  static bool insideWindow(std::uint32_t x, std::uint32_t y) { return x >= 10 && y >= 10 && y < kHeight - 10; }

  void SetUp() override {
    GpuTest::SetUp();
    createRenderer(kWidth, kHeight);
    addQuad({0.0f, 0.0f, 0.0f}, 1.5f, {0.9f, 0.3f, 0.2f, 1.0f});
  }
  CameraView camera() const { return CameraView::lookAt({0.0f, 0.0f, 2.0f}, {0.0f, 0.0f, 0.0f}, 0.9f, 0.05f, 4.0f / 3.0f); }
  gputest::Frame renderWithOverlay(engine::ui::UiLayer& ui) {
    ui.buildFrame(renderer_->extent(), 1.0f / 60.0f);
    engine::render::FrameSettings settings;
    settings.overlay = &ui;
    renderer_->renderFrame(registry_, camera(), settings);
    gputest::Frame frame;
    frame.width = kWidth;
    frame.height = kHeight;
    frame.rgba = renderer_->readbackColor();
    frame.depth = renderer_->readbackDepth();
    return frame;
  }
};

// Tricky: the layer draws in a render pass of its own after the scene, loading the colour target;
// a wrong load op, layout or dependency would clear or corrupt the scene outside the window, and
// panels drawn out of order or twice would scramble every feature's tuning panel.
TEST_F(UiLayerTest, PanelsDrawInOrderInsideTheWindowOverTheScene) {
  const gputest::Frame scene = render(camera());
  auto made = engine::ui::UiLayer::create(*context_, renderer_->desc().formats.color, renderer_->desc().framesInFlight, nullptr);
  ASSERT_TRUE(made) << made.error().message;
  std::unique_ptr<engine::ui::UiLayer> ui = std::move(*made);
  ui->setWindowTitle("ui layer test");
  std::vector<std::string> calls;
  ui->addPanel("first", [&] {
    calls.push_back("first");
    ImGui::TextUnformatted("first panel");
  });
  ui->addPanel("second", [&] {
    calls.push_back("second");
    ImGui::Button("a button", ImVec2(200.0f, 60.0f));
  });

  const gputest::Frame withUi = renderWithOverlay(*ui);
  EXPECT_EQ(calls, (std::vector<std::string>{"first", "second"}));
  EXPECT_FALSE(ui->wantsMouse());  // headless: no cursor over the window
  std::size_t changedInside = 0, changedOutside = 0;
  for (std::uint32_t y = 0; y < kHeight; ++y) {
    for (std::uint32_t x = 0; x < kWidth; ++x) {
      const bool changed = scene.pixel(x, y) != withUi.pixel(x, y);
      (insideWindow(x, y) ? changedInside : changedOutside) += changed ? 1 : 0;
    }
  }
  EXPECT_EQ(changedOutside, 0u) << "the overlay drew outside its window";
  EXPECT_GT(changedInside, std::size_t(kWidth * kHeight) / 4) << "the window's background and panels";
  EXPECT_EQ(scene.depth, withUi.depth) << "the overlay must not touch the prepass depth";

  // The next frame calls each panel once more, in the same order.
  renderWithOverlay(*ui);
  EXPECT_EQ(calls, (std::vector<std::string>{"first", "second", "first", "second"}));
}

// Tricky: a window resized down to a few pixels makes ImGui push the panel up and left until only a
// corner stays inside; resized back, the panel stayed there with its title bar above the display,
// out of reach of the mouse (found by driving the window with xdotool). Each frame the title bar is
// put back inside the display.
TEST_F(UiLayerTest, TheTitleBarComesBackInsideAfterATinyDisplay) {
  auto made = engine::ui::UiLayer::create(*context_, renderer_->desc().formats.color, renderer_->desc().framesInFlight, nullptr);
  ASSERT_TRUE(made) << made.error().message;
  std::unique_ptr<engine::ui::UiLayer> ui = std::move(*made);
  ImVec2 pos(-1.0f, -1.0f);
  ui->addPanel("where", [&] { pos = ImGui::GetWindowPos(); });
  for (int frame = 0; frame < 3; ++frame) ui->buildFrame({640, 400}, 1.0f / 60.0f);
  EXPECT_EQ(pos.x, 10.0f);
  EXPECT_EQ(pos.y, 10.0f);
  for (int frame = 0; frame < 3; ++frame) ui->buildFrame({10, 10}, 1.0f / 60.0f);
  for (int frame = 0; frame < 3; ++frame) ui->buildFrame({1200, 760}, 1.0f / 60.0f);
  EXPECT_GE(pos.y, 0.0f) << "the title bar is above the display";
  EXPECT_GE(pos.x, 0.0f);
  EXPECT_EQ(context_->validationMessageCount(), 0u);
}

// Tricky: ImGui's own writer dropped every error (a layout file in a read-only folder was not
// saved, without a word). The layout must reach the file a moment after a change and at shutdown
// (a change of the last seconds too, as ImGui did), and a file that cannot be written must be said
// once, naming it, however many times the layout changes, without failing a frame.
TEST_F(UiLayerTest, TheLayoutIsSavedAndAFileThatCannotBeWrittenIsSaidOnce) {
  const std::filesystem::path dir =
      std::filesystem::temp_directory_path() / ("hsdf_ui_layout_" + std::to_string(::getpid()));
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  auto warnings = std::make_unique<hsdftest::LogCapture>();
  const auto layoutWarnings = [&] { return warnings->count("window layout"); };
  {
    auto made = engine::ui::UiLayer::create(*context_, renderer_->desc().formats.color, renderer_->desc().framesInFlight, nullptr);
    ASSERT_TRUE(made) << made.error().message;
    std::unique_ptr<engine::ui::UiLayer> ui = std::move(*made);
    ui->setWindowTitle("layout test");
    bool change = false;
    ui->addPanel("changes", [&] {
      if (change) ImGui::MarkIniSettingsDirty();
    });
    ImGui::GetIO().IniSavingRate = 0.001f;  // saved the frame after a change (5 s by default)
    const auto changedFrames = [&](int frames) {
      change = true;
      ui->buildFrame({320, 240}, 1.0f / 60.0f);
      change = false;
      for (int frame = 1; frame < frames; ++frame) ui->buildFrame({320, 240}, 1.0f / 60.0f);
    };

    const std::filesystem::path saved = dir / "layout.ini";
    ui->setIniFile(saved.string());
    changedFrames(3);
    const auto text = engine::readTextFile(saved);
    ASSERT_TRUE(text) << "not saved after a change: " << text.error().message;
    EXPECT_NE(text->find("[Window][layout test]"), std::string::npos) << *text;
    EXPECT_EQ(layoutWarnings(), 0u);

    ui->setIniFile(dir.string());  // a folder: nothing to load from, and no file can be written there by that name
    EXPECT_EQ(layoutWarnings(), 2u) << "not loaded, and will not be saved: said when the file is set";
    for (int i = 0; i < 3; ++i) changedFrames(3);
    EXPECT_EQ(layoutWarnings(), 2u) << "said again at each change";
    ASSERT_EQ(warnings->messages().size(), 2u);
    for (const std::string& w : warnings->messages()) EXPECT_NE(w.find(dir.string()), std::string::npos) << w;

    ImGui::GetIO().IniSavingRate = 1000.0f;  // a change the running UI does not save...
    ui->setIniFile((dir / "at_exit.ini").string());
    changedFrames(2);
    EXPECT_FALSE(std::filesystem::exists(dir / "at_exit.ini"));
  }  // ... is saved at shutdown
  warnings.reset();
  EXPECT_TRUE(std::filesystem::exists(dir / "at_exit.ini"));
  std::filesystem::remove_all(dir);
  EXPECT_EQ(context_->validationMessageCount(), 0u);
}

}  // namespace
