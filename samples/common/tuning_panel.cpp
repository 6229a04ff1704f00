#include "tuning_panel.h"

#include <algorithm>
#include <vector>

#include <fmt/format.h>
#include <imgui.h>

#include "viewer.h"

namespace samples {
namespace {

double mebibytes(std::uint64_t bytes) { return double(bytes) / (1024.0 * 1024.0); }

// Method names in the order of the Method enum.
constexpr const char* kMethodLabels[] = {"mesh (triangles)", "Hermite cells (the paper)", "trilinear sphere tracing",
                                         "dense Hermite sphere tracing"};
constexpr const char* kDebugViewLabels[] = {"shaded", "normals", "depth", "cells", "evaluations", "cell boxes"};

bool sliderU32(const char* label, std::uint32_t& value, IntRange range) {
  int v = int(value);
  if (!ImGui::SliderInt(label, &v, range.min, range.max)) return false;
  value = std::uint32_t(v);
  return true;
}

// A one-line scrolling plot of the samples seen so far (the last kSamples once full).
void plot(const char* label, const PlotHistory& history) {
  const int count = std::min(history.count, PlotHistory::kSamples);
  const int offset = history.count < PlotHistory::kSamples ? 0 : history.next;
  const float top = count > 0 ? *std::max_element(history.values.begin(), history.values.begin() + count) : 0.0f;
  ImGui::SameLine(262.0f);
  ImGui::PlotLines(label, history.values.data(), count, offset, nullptr, 0.0f, std::max(top * 1.1f, 1e-3f),
                   ImVec2(130.0f, 16.0f));
}

}  // namespace

void PlotHistory::push(float value) {
  values[std::size_t(next)] = value;
  next = (next + 1) % kSamples;
  ++count;
}

void TuningPanel::draw() {
  drawMethod();
  drawResolution();
  drawStatistics();
  drawTimings();
  drawFiles();
  drawWindow();
}

// Everything here writes the TuningState (applied at the next frame), nothing else.
void TuningPanel::drawMethod() {
  TuningState t = viewer_.tuning();
  bool changed = false;
  int method = int(t.method);
  const bool sdf = viewer_.sdfAsset() || viewer_.canRebake();
  if (ImGui::BeginCombo("method", kMethodLabels[method])) {
    for (int m = 0; m < 4; ++m) {
      const bool available = m == int(Method::Mesh) ? viewer_.hasMeshes() : sdf;
      if (available && ImGui::Selectable(kMethodLabels[m], m == method)) {
        t.method = Method(m);
        changed = true;
      }
    }
    ImGui::EndCombo();
  }
  changed |= sliderU32("n (subdivisions)", t.subdivisions, kPanelSubdivisionsRange);
  changed |= sliderU32("refinement", t.refineSteps, kPanelRefineRange);
  bool exact = t.normals == hsdf::NormalMode::Exact;
  if (ImGui::Checkbox("exact normals (off: central diff.)", &exact)) {
    t.normals = exact ? hsdf::NormalMode::Exact : hsdf::NormalMode::CentralDifferences;
    changed = true;
  }
  changed |= ImGui::Checkbox("fp16", &t.fp16);
  ImGui::SameLine();
  changed |= ImGui::Checkbox("front to back", &t.frontToBack);
  ImGui::SameLine();
  changed |= ImGui::Checkbox("certified roots", &t.certified);
  if (ImGui::IsItemHovered())
    ImGui::SetTooltip("cells: Bernstein subdivision of the ray's cubic instead of n samples; never misses the first root");
  int view = int(t.debugView);
  if (ImGui::Combo("debug view", &view, kDebugViewLabels, IM_ARRAYSIZE(kDebugViewLabels))) {
    t.debugView = DebugView(view);
    changed = true;
  }
  if (changed) viewer_.setTuning(t);
}

// K re-bakes when the slider is released (not at every value dragged over).
void TuningPanel::drawResolution() {
  if (!viewer_.canRebake()) {
    if (const hsdf::SdfAsset* asset = viewer_.sdfAsset())
      ImGui::Text("K %d (fixed: drawn from a .hsdf file)", asset->cells.grid.resolution);
    if (!viewer_.bakeError().empty()) ImGui::TextWrapped("cannot bake: %s", viewer_.bakeError().c_str());
    return;
  }
  TuningState t = viewer_.tuning();
  if (!ImGui::IsAnyItemActive()) resolution_ = t.resolution;
  ImGui::SliderInt("K (resolution)", &resolution_, kPanelResolutionRange.min, kPanelResolutionRange.max);
  if (ImGui::IsItemDeactivatedAfterEdit() && resolution_ != t.resolution) {
    t.resolution = resolution_;
    viewer_.setTuning(t);
  }
  if (hsdf::BakeJob* job = viewer_.bakeJob()) {
    const std::string label = fmt::format("baking K = {}: {:.0f}%", job->settings().resolution, 100.0f * job->progress());
    ImGui::ProgressBar(job->progress(), ImVec2(-80.0f, 0.0f), label.c_str());
    ImGui::SameLine();
    if (ImGui::Button("cancel")) viewer_.cancelBake();
  }
  if (!viewer_.bakeError().empty()) ImGui::TextWrapped("bake refused/failed: %s", viewer_.bakeError().c_str());
}

void TuningPanel::drawStatistics() {
  const hsdf::SdfAsset* asset = viewer_.sdfAsset();
  if (!asset || !ImGui::CollapsingHeader("Cells and storage", ImGuiTreeNodeFlags_DefaultOpen)) return;
  const SdfStats s = sdfStats(*asset);
  ImGui::Text("K = %d: %llu cells", s.resolution, static_cast<unsigned long long>(s.cells.cells));
  ImGui::Text("%llu crossing, %llu ambiguous, %llu empty", static_cast<unsigned long long>(s.cells.crossing),
              static_cast<unsigned long long>(s.cells.ambiguous), static_cast<unsigned long long>(s.cells.empty));
  // Fixed widths: measured ones are only known from the second frame (a one-frame headless
  // screenshot would show squeezed columns).
  if (ImGui::BeginTable("storage", 3, ImGuiTableFlags_Borders)) {
    ImGui::TableSetupColumn("method", ImGuiTableColumnFlags_WidthFixed, 150.0f);
    ImGui::TableSetupColumn("stored scalars", ImGuiTableColumnFlags_WidthFixed, 100.0f);
    ImGui::TableSetupColumn("MiB fp32 / fp16", ImGuiTableColumnFlags_WidthFixed, 105.0f);
    ImGui::TableHeadersRow();
    auto row = [](const char* name, std::uint64_t scalars, std::uint64_t bytes32, std::uint64_t bytes16) {
      ImGui::TableNextRow();
      ImGui::TableNextColumn();
      ImGui::TextUnformatted(name);
      ImGui::TableNextColumn();
      ImGui::Text("%llu", static_cast<unsigned long long>(scalars));
      ImGui::TableNextColumn();
      ImGui::Text("%.2f / %.2f", mebibytes(bytes32), mebibytes(bytes16));
    };
    row("Hermite cells", s.cellScalars, s.cellBytes, s.cellBytesHalf);
    row("trilinear (K^3)", s.trilinearScalars, 4 * s.trilinearScalars, 2 * s.trilinearScalars);
    row("dense Hermite (4K^3)", s.hermiteScalars, 4 * s.hermiteScalars, 2 * s.hermiteScalars);
    ImGui::EndTable();
  }
}

// Numbers for this frame, in the renderer's pass order, each with its plot over the last seconds.
void TuningPanel::drawTimings() {
  const float frameMs = 1000.0f * viewer_.frameSeconds();
  frameHistory_.push(frameMs);
  const std::vector<engine::gpu::GpuTiming>& timings = viewer_.renderer().lastTimings();
  for (const engine::gpu::GpuTiming& t : timings) gpuHistory_[t.name].push(float(t.milliseconds));
  if (!ImGui::CollapsingHeader("Frame and GPU times (plots: last 240 frames)", ImGuiTreeNodeFlags_DefaultOpen)) return;
  ImGui::Text("%-17s %9.2f ms", "frame (wall)", double(frameMs));
  plot("##frame", frameHistory_);
  for (const engine::gpu::GpuTiming& t : timings) {
    ImGui::Text("GPU %-13s %9.2f ms", t.name.c_str(), t.milliseconds);
    plot(("##" + t.name).c_str(), gpuHistory_[t.name]);
  }
}

void TuningPanel::drawFiles() {
  if (!ImGui::CollapsingHeader("Screenshot and settings")) return;
  ImGui::InputText("PNG", screenshotPath_.data(), screenshotPath_.size());
  ImGui::SameLine();
  if (ImGui::Button("screenshot")) viewer_.requestScreenshot(screenshotPath_.data());
  ImGui::InputText("settings", settingsPath_.data(), settingsPath_.size());
  if (ImGui::Button("save settings")) {
    const engine::Status saved = saveTuning(settingsPath_.data(), viewer_.tuning());
    viewer_.setStatusLine(saved ? fmt::format("saved {}", settingsPath_.data()) : saved.error().message);
  }
  ImGui::SameLine();
  if (ImGui::Button("load settings")) {
    auto loaded = loadTuning(settingsPath_.data(), viewer_.tuning());
    if (loaded) viewer_.setTuning(*loaded);
    viewer_.setStatusLine(loaded ? fmt::format("loaded {}", settingsPath_.data()) : loaded.error().message);
  }
  if (!viewer_.statusLine().empty()) ImGui::TextWrapped("%s", viewer_.statusLine().c_str());
}

void TuningPanel::drawWindow() {
  int mode = int(viewer_.cameraMode());
  ImGui::TextUnformatted("camera");
  ImGui::SameLine();
  bool changed = ImGui::RadioButton("orbit", &mode, int(CameraMode::Orbit));
  ImGui::SameLine();
  changed |= ImGui::RadioButton("fly", &mode, int(CameraMode::Fly));
  if (changed) viewer_.setCameraMode(CameraMode(mode));
  ImGui::TextWrapped(viewer_.cameraMode() == CameraMode::Orbit
                         ? "Orbit: left-drag rotates, right-drag or scroll zooms, middle-drag pans."
                         : "Fly: W/A/S/D moves, Q/E down/up, Shift faster, right-drag looks.");
  ImGui::TextWrapped("F1: panel on/off, F2: orbit/fly, F11: full screen.");
  if (!viewer_.windowed()) return;
  bool vsync = viewer_.vsync();
  if (ImGui::Checkbox("V-sync", &vsync)) {
    const engine::Status set = viewer_.setVsync(vsync);
    if (!set) viewer_.setStatusLine(set.error().message);
  }
  ImGui::SameLine();
  bool fullscreen = viewer_.fullscreen();
  if (ImGui::Checkbox("full screen", &fullscreen)) viewer_.setFullscreen(fullscreen);
}

}  // namespace samples
