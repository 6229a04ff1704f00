#pragma once
// The tuning panel of the scene runner (ImGui, in the engine's panel registry): method, n,
// refinement, normals, fp16, front to back and the debug view are written into a TuningState that
// Viewer::setTuning applies at the next frame (the same path --settings and --script take); K
// re-bakes on the worker thread with a progress bar and a cancel button. Also: cell and storage
// statistics, GPU time per pass with a scrolling plot, screenshot and settings buttons, the camera
// help line, V-sync and full screen. The comparison: split screen with a divider dragged in the
// frame, the compared method's K and normals, the difference view's legend and numbers; and the
// "Reload shaders" button with each feature's result.
#include <array>
#include <map>
#include <string>

namespace samples {

class Viewer;
struct TuningState;

// The last `kSamples` values of one series, oldest first from `next` once `count` reaches kSamples.
struct PlotHistory {
  static constexpr int kSamples = 240;  // 4 s at 60 Hz
  std::array<float, kSamples> values{};
  int next = 0;
  int count = 0;  // values pushed so far
  void push(float value);
};

class TuningPanel {
 public:
  explicit TuningPanel(Viewer& viewer) : viewer_(viewer) {}
  // Inside the ImGui frame (a UiLayer panel).
  void draw();
  // The panel's one way to change the tuning: a state that validateTuning or Viewer::checkTuning
  // refuses is not applied, and the reason is shown at the top of the panel until a change is
  // applied (the controls' ranges and choices should never produce one: this is the backstop).
  bool apply(const TuningState& tuning);
  const std::string& refusal() const { return refusal_; }

 private:
  void drawMethod();
  void drawResolution();
  void drawShell(const TuningState& tuning);
  void drawLod(const TuningState& tuning);
  void drawSearchLimits(const TuningState& tuning);
  void drawComparison();
  void drawDifferenceLegend();
  void drawDivider();
  void drawShaders();
  void drawStatistics();
  void drawTimings();
  void drawFiles();
  void drawWindow();
  void drawSceneCameras();

  Viewer& viewer_;
  std::map<std::string, PlotHistory> gpuHistory_;  // per pass name
  PlotHistory frameHistory_;
  int resolution_ = 0;  // the K slider while it is dragged (re-bakes on release)
  int compareResolution_ = 0;  // the same for the compared side
  float shell_ = 0.0f;         // the shell thickness while it is dragged (re-bakes on release)
  std::array<char, 256> screenshotPath_{"hsdf_screenshot.png"};
  std::array<char, 256> settingsPath_{"hsdf_settings.json"};
  std::string refusal_;  // why the last change was refused (apply), until one is applied
};

}  // namespace samples
