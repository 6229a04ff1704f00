#include "tuning_panel.h"

#include <algorithm>
#include <cmath>
#include <vector>

#include <fmt/format.h>
#include <imgui.h>

#include "engine/core/log.h"
#include "engine/gpu/pipeline.h"
#include "tuning_fields.h"
#include "viewer.h"

namespace samples {
namespace {

double mebibytes(std::uint64_t bytes) { return double(bytes) / (1024.0 * 1024.0); }

// The panel's words for the methods, in the order of allMethods() (mesh, then hsdf::kRenderMethods).
constexpr const char* kMethodLabels[] = {"mesh (triangles)", "Hermite cells (the paper)", "trilinear sphere tracing",
                                         "dense Hermite sphere tracing", "Hermite cells, runs along x",
                                         "Hermite cells, 4x4x4 bricks"};
static_assert(std::size(kMethodLabels) == 1 + std::size(hsdf::kRenderMethods), "a label per method");
// The panel's words for the debug views, by DEBUG_VIEW_* value.
constexpr const char* kDebugViewLabels[] = {"shaded", "normals", "depth", "cells", "evaluations", "cell boxes"};
static_assert(std::size(kDebugViewLabels) == std::size(shader::kDebugViewNames), "a label per debug view");

// The place of `method` in allMethods(), the index of its label.
int methodIndex(Method method) {
  const std::vector<Method> methods = allMethods();
  return int(std::find(methods.begin(), methods.end(), method) - methods.begin());
}

// Every slider clamps what is typed into it (ctrl+click) to its range: without it ImGui took n = 200,
// a central-difference step of 0 (a black object) or K = 3000 past the sliders' ends.
constexpr ImGuiSliderFlags kClamp = ImGuiSliderFlags_AlwaysClamp;

// A bake's progress bar ("WHAT K = k: p%") with its cancel button; true when it was pressed.
bool bakeProgress(const hsdf::BakeJob& job, const char* what, const char* cancelId) {
  const std::string label = fmt::format("{} K = {}: {:.0f}%", what, job.settings().resolution, 100.0f * job.progress());
  ImGui::ProgressBar(job.progress(), ImVec2(-80.0f, 0.0f), label.c_str());
  ImGui::SameLine();
  return ImGui::Button(cancelId);
}

// The table's words for a control (tuning_fields.h): its label, and its help as the tooltip,
// wrapped (the help is one line, written for --help too).
const char* label(std::string_view key) { return tuningField(key).label; }
void tooltip(std::string_view key) {
  if (!ImGui::IsItemHovered()) return;
  ImGui::BeginTooltip();
  ImGui::PushTextWrapPos(ImGui::GetFontSize() * 40.0f);
  ImGui::TextUnformatted(tuningField(key).help.c_str());
  ImGui::PopTextWrapPos();
  ImGui::EndTooltip();
}

template <class T>
T& member(std::string_view key, TuningState& t) {
  return t.*std::get<T TuningState::*>(tuningField(key).member);
}

// A bool setting's checkbox; true when the user changed it.
bool checkbox(std::string_view key, TuningState& t) {
  const bool changed = ImGui::Checkbox(label(key), &member<bool>(key, t));
  tooltip(key);
  return changed;
}

// An integer setting's slider over `range` (the panel's, where it is narrower than the table's).
bool sliderU32(std::string_view key, TuningState& t, IntRange range) {
  std::uint32_t& value = member<std::uint32_t>(key, t);
  int v = int(value);
  const bool changed = ImGui::SliderInt(label(key), &v, range.min, range.max, "%d", kClamp);
  tooltip(key);
  if (changed) value = std::uint32_t(v);
  return changed;
}
bool sliderU32(std::string_view key, TuningState& t) {
  const NumberRange range = tuningField(key).range;
  return sliderU32(key, t, IntRange{int(range.min), int(range.max)});
}

// A float setting's slider over the table's range.
bool sliderFloat(std::string_view key, TuningState& t, const char* format, ImGuiSliderFlags flags = 0) {
  const NumberRange range = tuningField(key).range;
  const bool changed =
      ImGui::SliderFloat(label(key), &member<float>(key, t), float(range.min), float(range.max), format, flags | kClamp);
  tooltip(key);
  return changed;
}

// The width of an auto / on / off combo (autoSwitchCombo).
float autoSwitchComboWidth() { return ImGui::GetFontSize() * 4.0f; }

// The width the next control with a label takes: `field` (a frame, a checkbox's box) and the label.
float labelledWidth(float field, const char* text) {
  return field + ImGui::GetStyle().ItemInnerSpacing.x + ImGui::CalcTextSize(text, nullptr, true).x;
}
float checkboxWidth(std::string_view key) { return labelledWidth(ImGui::GetFrameHeight(), label(key)); }
float autoSwitchWidth(std::string_view key) { return labelledWidth(autoSwitchComboWidth(), label(key)); }

// The next control, `width` pixels wide, on the line of the last one where it fits in the panel,
// else on the next line: a row of toggles ran past the panel's right edge, where ImGui clips them
// (in a 420-pixel panel, "certified" was cut and "cull cells", "proxy boxes" and "thin boxes" could
// not be reached).
void sameLineIfFits(float width) {
  ImGui::SameLine();
  if (ImGui::GetContentRegionAvail().x < width) ImGui::NewLine();
}

// The sliders' and combos' width: the panel's less its longest label, at least 45 % of it. ImGui's
// default, 65 % of the panel, cut "central difference step (h)" and "upload MiB/frame (0: no limit)".
float controlWidth() {
  float widest = 0.0f;
  for (const TuningField& field : tuningFields())
    if (const TuningKind kind = tuningKind(field); kind == TuningKind::Number || kind == TuningKind::Name)
      widest = std::max(widest, ImGui::CalcTextSize(field.label, nullptr, true).x);
  const float panel = ImGui::GetContentRegionAvail().x;
  return std::max(0.45f * panel, panel - widest - ImGui::GetStyle().ItemInnerSpacing.x);
}

// A narrow auto / on / off combo of an AutoSwitch setting; true when the user changed it.
bool autoSwitchCombo(std::string_view key, TuningState& t) {
  static_assert(int(AutoSwitch::Auto) == 0 && int(AutoSwitch::On) == 1 && int(AutoSwitch::Off) == 2);
  AutoSwitch& value = member<AutoSwitch>(key, t);
  int index = int(value);
  ImGui::SetNextItemWidth(autoSwitchComboWidth());
  const bool changed = ImGui::Combo(label(key), &index, "auto\0on\0off\0");  // the enum's order
  if (changed) value = AutoSwitch(index);
  tooltip(key);
  return changed;
}

// A normals setting as a checkbox: exact, or off for central differences.
bool exactNormals(std::string_view key, TuningState& t) {
  hsdf::NormalMode& normals = member<hsdf::NormalMode>(key, t);
  bool exact = normals == hsdf::NormalMode::Exact;
  const bool changed = ImGui::Checkbox(label(key), &exact);
  tooltip(key);
  if (changed) normals = exact ? hsdf::NormalMode::Exact : hsdf::NormalMode::CentralDifferences;
  return changed;
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
  ImGui::PushItemWidth(controlWidth());
  if (!refusal_.empty()) ImGui::TextColored(ImVec4(1.0f, 0.45f, 0.35f, 1.0f), "refused: %s", refusal_.c_str());
  drawMethod();
  drawResolution();
  drawComparison();
  drawDivider();
  drawDifferenceLegend();
  drawShaders();
  drawStatistics();
  drawTimings();
  drawFiles();
  drawWindow();
  ImGui::PopItemWidth();
}

bool TuningPanel::apply(const TuningState& tuning) {
  engine::Status valid = validateTuning(tuning);
  if (valid) valid = viewer_.checkTuning(tuning);
  if (!valid) {
    refusal_ = valid.error().message;
    engine::log::warn("panel: {}", refusal_);
    return false;
  }
  refusal_.clear();
  viewer_.setTuning(tuning);
  return true;
}

// Everything here writes the TuningState (applied at the next frame), nothing else.
void TuningPanel::drawMethod() {
  TuningState t = viewer_.tuning();
  bool changed = false;
  int method = methodIndex(t.method);
  const bool sdf = viewer_.sdfAsset() || viewer_.canRebake();
  if (ImGui::BeginCombo(label("method"), kMethodLabels[method])) {
    for (int m = 0; m < int(std::size(kMethodLabels)); ++m) {
      const bool available = m == methodIndex(Method::Mesh) ? viewer_.hasMeshes() : sdf;
      if (available && ImGui::Selectable(kMethodLabels[m], m == method)) {
        t.method = allMethods()[std::size_t(m)];
        // A dense tracer stops at a lower K than the cells: the switch bakes at its limit.
        t.resolution = std::min(t.resolution, resolutionRange(t.method).max);
        changed = true;
      }
    }
    ImGui::EndCombo();
  }
  changed |= sliderU32("subdivisions", t, kPanelSubdivisionsRange);
  changed |= sliderU32("refine", t, kPanelRefineRange);
  changed |= exactNormals("normals", t);
  changed |= checkbox("fp16", t);
  sameLineIfFits(checkboxWidth("front_to_back"));
  changed |= checkbox("front_to_back", t);
  sameLineIfFits(autoSwitchWidth("early_depth"));
  changed |= autoSwitchCombo("early_depth", t);
  for (const char* key : {"certified", "cull_bricks", "cull_cells", "cull_occlusion", "proxy_boxes"}) {
    sameLineIfFits(checkboxWidth(key));
    changed |= checkbox(key, t);
  }
  sameLineIfFits(autoSwitchWidth("thin_boxes"));
  changed |= autoSwitchCombo("thin_boxes", t);
  changed |= autoSwitchCombo("tiles", t);
  if (t.tiles != AutoSwitch::Off) {
    static constexpr const char* kTileSizeLabels[] = {"4x4", "8x8", "16x16"};
    static_assert(std::size(kTileSizeLabels) == std::size(kTileSizes));
    int size = int(std::find(std::begin(kTileSizes), std::end(kTileSizes), t.tileSize) - std::begin(kTileSizes));
    if (ImGui::Combo(label("tile_size"), &size, kTileSizeLabels, IM_ARRAYSIZE(kTileSizeLabels))) {
      t.tileSize = kTileSizes[size];
      changed = true;
    }
    tooltip("tile_size");
  }
  int view = int(t.debugView);
  if (ImGui::Combo(label("debug_view"), &view, kDebugViewLabels, IM_ARRAYSIZE(kDebugViewLabels))) {
    t.debugView = DebugView(view);
    changed = true;
  }
  tooltip("debug_view");
  if (changed) apply(t);
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
  // The method's range (cells 2048, dense tracers 512), logarithmic: 8..2048 on one slider.
  const int top = std::min(kPanelResolutionRange.max, resolutionRange(t.method).max);
  ImGui::SliderInt(label("resolution"), &resolution_, kPanelResolutionRange.min, top, "%d", ImGuiSliderFlags_Logarithmic | kClamp);
  if (ImGui::IsItemHovered())
    ImGui::SetTooltip("K up to %d for %s; cells past %d bake sparse (the bake budget may refuse, naming its limit)", top,
                      methodName(t.method), kDenseBakeMaxResolution);
  if (ImGui::IsItemDeactivatedAfterEdit() && resolution_ != t.resolution) {
    t.resolution = resolution_;
    apply(t);
  }
  drawShell(viewer_.tuning());
  drawLod(viewer_.tuning());
  drawSearchLimits(viewer_.tuning());
  if (const hsdf::BakeJob* job = viewer_.bakeJob()) {
    if (bakeProgress(*job, "baking", "cancel")) viewer_.cancelBake();
  } else if (const hsdf::BakeJob* level = viewer_.levelBakeJob()) {
    if (bakeProgress(*level, "level of detail", "cancel##level")) viewer_.cancelBake();
  }
  if (!viewer_.bakeError().empty()) ImGui::TextWrapped("bake refused/failed: %s", viewer_.bakeError().c_str());
}

// The shell thickness (TuningState::shellThickness) in scene units, dragged a hundredth of a grid
// cell per step and re-baked on release, as K is. Below a cell both faces lie between the same
// samples, so the panel says so beside it.
void TuningPanel::drawShell(const TuningState& tuning) {
  TuningState t = tuning;
  if (!ImGui::IsAnyItemActive()) shell_ = t.shellThickness;
  const hsdf::SdfAsset* asset = viewer_.sdfAsset();
  const float cell = asset ? float(asset->cells.grid.spacing) : 0.0f;
  const NumberRange range = tuningField("shell").range;
  ImGui::DragFloat(label("shell"), &shell_, std::max(0.01f * cell, 1e-6f), float(range.min), float(range.max), "%.4g",
                   kClamp);
  tooltip("shell");
  if (ImGui::IsItemDeactivatedAfterEdit() && shell_ != t.shellThickness) {
    t.shellThickness = shell_;
    apply(t);
  }
  if (t.shellThickness > 0.0f && t.shellThickness < cell)
    ImGui::TextWrapped("thinner than a grid cell (%.4g): it draws rough, or with holes", double(cell));
}

// Levels of detail: on/off and the target cell size (TuningState::lod, lodPixelsPerCell).
void TuningPanel::drawLod(const TuningState& tuning) {
  TuningState t = tuning;
  bool changed = checkbox("lod", t);
  if (t.lod) {
    ImGui::SameLine();
    ImGui::SetNextItemWidth(ImGui::GetFontSize() * 8.0f);
    changed |= sliderFloat("lod_pixels_per_cell", t, "%.2f", ImGuiSliderFlags_Logarithmic);
  }
  if (changed) apply(t);
}

// The sphere tracers' stopping rule and normals step, the runs' length (TuningState::traceEpsilon,
// traceMaxSteps, centralDifferenceStep, maxRunLength), shown for the methods they change.
void TuningPanel::drawSearchLimits(const TuningState& tuning) {
  TuningState t = tuning;
  bool changed = false;
  const auto tracing = [](Method m) { return m == hsdf::RenderMethod::TrilinearSphereTrace || m == hsdf::RenderMethod::HermiteSphereTrace; };
  const bool tracer = tracing(t.method) || (comparing(t) && tracing(t.compareMethod));
  if (tracer) {
    // Epsilon spans five decades: its slider moves its logarithm.
    const NumberRange epsilon = tuningField("trace_epsilon").range;
    float logEpsilon = std::log10(t.traceEpsilon);
    if (ImGui::SliderFloat(label("trace_epsilon"), &logEpsilon, std::log10(float(epsilon.min)),
                           std::log10(float(epsilon.max)), "%.1f", kClamp)) {
      t.traceEpsilon = std::clamp(std::pow(10.0f, logEpsilon), float(epsilon.min), float(epsilon.max));
      changed = true;
    }
    tooltip("trace_epsilon");
    changed |= sliderU32("trace_max_steps", t);
    changed |= sliderFloat("central_difference_step", t, "%.2f");
  }
  if (t.method == hsdf::RenderMethod::CellRuns) changed |= sliderU32("max_run_length", t);
  if (const auto sdf = t.method.sdf(); sdf && hsdf::drawsCells(*sdf))
    changed |= sliderU32("upload_mib_per_frame", t, IntRange{0, 256});
  if (changed) apply(t);
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
    // The compared side's own field (e.g. trilinear at 2K), when it has one.
    const TuningState& t = viewer_.tuning();
    const auto k = std::uint64_t(viewer_.compareResolutionDrawn());
    if (comparing(t) && !drawsCells(t.compareMethod) && k != std::uint64_t(s.resolution)) {
      const std::uint64_t scalars = (t.compareMethod == hsdf::RenderMethod::HermiteSphereTrace ? 4 : 1) * k * k * k;
      const std::string label = fmt::format("compared, K {}", k);
      row(label.c_str(), scalars, 4 * scalars, 2 * scalars);
    }
    ImGui::EndTable();
    if (!s.denseField) ImGui::TextDisabled("no dense field held (cells only): the K^3 rows are what the tracers would store");
  }
}

// Split screen / difference view: what is compared with what; writes the TuningState.
void TuningPanel::drawComparison() {
  if (!ImGui::CollapsingHeader("Compare (split screen, difference view)", ImGuiTreeNodeFlags_DefaultOpen)) return;
  TuningState t = viewer_.tuning();
  TuningState splitOn = t;
  splitOn.split = SplitMode::Vertical;
  if (const engine::Status drawable = viewer_.checkTuning(splitOn); !drawable) {  // a scene of separate objects
    ImGui::TextWrapped("%s", drawable.error().message.c_str());
    return;
  }
  bool changed = false;
  int split = int(t.split);
  ImGui::TextUnformatted(label("split"));
  tooltip("split");
  for (int mode = 0; mode < 3; ++mode) {
    ImGui::SameLine();
    changed |= ImGui::RadioButton(splitModeName(SplitMode(mode)), &split, mode);
  }
  t.split = SplitMode(split);
  if (t.split != SplitMode::Off) changed |= sliderFloat("split_position", t, "%.2f");
  int compared = methodIndex(t.compareMethod) - 1;  // the SDF methods: cells, trilinear, hermite
  if (ImGui::Combo(label("compare_method"), &compared, kMethodLabels + 1, 3)) {
    t.compareMethod = allMethods()[std::size_t(compared + 1)];
    changed = true;
  }
  if (!drawsCells(t.compareMethod) && viewer_.canRebake()) {
    // 0 = the rule of thumb (2K); re-bakes on release, like K.
    if (!ImGui::IsAnyItemActive()) compareResolution_ = t.compareResolution;
    ImGui::SliderInt(label("compare_resolution"), &compareResolution_, 0, resolutionRange(t.compareMethod).max, "%d", kClamp);
    tooltip("compare_resolution");
    if (ImGui::IsItemDeactivatedAfterEdit() && compareResolution_ != t.compareResolution) {
      t.compareResolution = compareResolution_ == 0 ? 0 : std::max(compareResolution_, kPanelResolutionRange.min);
      changed = true;
    }
  }
  changed |= exactNormals("compare_normals", t);
  changed |= checkbox("difference", t);
  if (comparing(t))
    ImGui::Text("%s, K %d  |  %s, K %d", methodName(t.method), viewer_.resolutionDrawn(), methodName(t.compareMethod),
                viewer_.compareResolutionDrawn());
  if (const hsdf::BakeJob* job = viewer_.compareBakeJob())
    if (bakeProgress(*job, "compared side", "cancel##compare")) viewer_.cancelBake();
  if (!viewer_.compareBakeError().empty()) ImGui::TextWrapped("%s", viewer_.compareBakeError().c_str());
  if (t.difference && !isSdfMethod(t.method)) ImGui::TextWrapped("the difference view compares two SDF methods");
  if (changed) apply(t);
}

// A handle over the divider, dragged in the frame (an ImGui window, so the camera does not take
// the drag), and each side's method written at the top of its half.
void TuningPanel::drawDivider() {
  TuningState t = viewer_.tuning();
  if (t.split == SplitMode::Off || t.difference) return;
  const ImVec2 display = ImGui::GetIO().DisplaySize;
  const bool vertical = t.split == SplitMode::Vertical;
  const float at = t.splitPosition * (vertical ? display.x : display.y);
  constexpr float kGrip = 10.0f;
  ImGui::SetNextWindowPos(vertical ? ImVec2(at - kGrip * 0.5f, 0.0f) : ImVec2(0.0f, at - kGrip * 0.5f));
  ImGui::SetNextWindowSize(vertical ? ImVec2(kGrip, display.y) : ImVec2(display.x, kGrip));
  ImGui::PushStyleVar(ImGuiStyleVar_WindowPadding, ImVec2(0.0f, 0.0f));
  ImGui::PushStyleVar(ImGuiStyleVar_WindowMinSize, ImVec2(1.0f, 1.0f));
  const ImGuiWindowFlags flags = ImGuiWindowFlags_NoDecoration | ImGuiWindowFlags_NoBackground |
                                 ImGuiWindowFlags_NoMove | ImGuiWindowFlags_NoSavedSettings |
                                 ImGuiWindowFlags_NoFocusOnAppearing | ImGuiWindowFlags_NoBringToFrontOnFocus;
  if (ImGui::Begin("##split divider", nullptr, flags)) {
    ImGui::InvisibleButton("##grip", ImGui::GetWindowSize());
    const bool active = ImGui::IsItemActive();
    if (ImGui::IsItemHovered() || active)
      ImGui::SetMouseCursor(vertical ? ImGuiMouseCursor_ResizeEW : ImGuiMouseCursor_ResizeNS);
    if (active) {
      const ImVec2 mouse = ImGui::GetIO().MousePos;
      t.splitPosition =
          std::clamp(vertical ? mouse.x / display.x : mouse.y / display.y, kSplitPositionRange.min, kSplitPositionRange.max);
      apply(t);
    }
    // Behind the other windows, as the handle is: where the panel covers the divider, the panel
    // takes the mouse, so the line is not drawn there either (it was drawn over the panel, where
    // it could not be grabbed).
    ImDrawList* draw = ImGui::GetBackgroundDrawList();
    const ImU32 color = active ? IM_COL32(255, 220, 80, 255) : IM_COL32(255, 255, 255, 200);
    if (vertical) draw->AddLine(ImVec2(at, 0.0f), ImVec2(at, display.y), color, 2.0f);
    else draw->AddLine(ImVec2(0.0f, at), ImVec2(display.x, at), color, 2.0f);
    const std::string left = fmt::format("{} K {}", methodName(t.method), viewer_.resolutionDrawn());
    const std::string right = fmt::format("{} K {}", methodName(t.compareMethod), viewer_.compareResolutionDrawn());
    // Labels at the bottom beside a vertical divider, at the right end of a horizontal one (the
    // panel is on the left).
    // Kept inside the image with the divider at either end of its range.
    const float leftWidth = ImGui::CalcTextSize(left.c_str()).x, rightWidth = ImGui::CalcTextSize(right.c_str()).x;
    const auto inside = [&display](ImVec2 p, float width) {
      return ImVec2(std::clamp(p.x, 4.0f, std::max(4.0f, display.x - width - 4.0f)),
                    std::clamp(p.y, 4.0f, std::max(4.0f, display.y - 20.0f)));
    };
    const ImVec2 leftAt =
        vertical ? ImVec2(at - 8.0f - leftWidth, display.y - 20.0f) : ImVec2(display.x - leftWidth - 8.0f, at - 22.0f);
    const ImVec2 rightAt = vertical ? ImVec2(at + 8.0f, display.y - 20.0f) : ImVec2(display.x - rightWidth - 8.0f, at + 6.0f);
    draw->AddText(inside(leftAt, leftWidth), IM_COL32_WHITE, left.c_str());
    draw->AddText(inside(rightAt, rightWidth), IM_COL32_WHITE, right.c_str());
  }
  ImGui::End();
  ImGui::PopStyleVar(2);
}

// The heat map's legend (degrees) and the last difference frame's numbers.
void TuningPanel::drawDifferenceLegend() {
  const std::optional<NormalDifference>& d = viewer_.difference();
  if (!d) return;
  float range = viewer_.differenceRange();
  if (ImGui::SliderFloat("red at (deg)", &range, 0.5f, 90.0f, "%.1f", ImGuiSliderFlags_Logarithmic | kClamp))
    viewer_.setDifferenceRange(range);
  // A colour bar with ticks at 0, 1/2 and the full range; white: covered by one method only.
  const ImVec2 origin = ImGui::GetCursorScreenPos();
  const float width = std::max(ImGui::GetContentRegionAvail().x - 10.0f, 50.0f), height = 14.0f;
  ImDrawList* draw = ImGui::GetWindowDrawList();
  constexpr int kSteps = 32;
  for (int i = 0; i < kSteps; ++i) {
    const glm::vec3 c = heatColor(range * (float(i) + 0.5f) / float(kSteps), range);
    draw->AddRectFilled(ImVec2(origin.x + width * float(i) / kSteps, origin.y),
                        ImVec2(origin.x + width * float(i + 1) / kSteps, origin.y + height),
                        ImGui::ColorConvertFloat4ToU32(ImVec4(c.r, c.g, c.b, 1.0f)));
  }
  ImGui::Dummy(ImVec2(width, height));
  ImGui::Text("0 deg");
  ImGui::SameLine(width * 0.5f - 10.0f);
  ImGui::Text("%.1f", double(range) * 0.5);
  ImGui::SameLine(width - 50.0f);
  ImGui::Text("%.1f deg", double(range));
  ImGui::TextWrapped("normal angle: mean %.2f deg, max %.1f deg over %llu pixels", d->meanDegrees, d->maxDegrees,
                     static_cast<unsigned long long>(d->coveredBoth));
  ImGui::TextWrapped("coverage differs (white): %llu of %llu pixels (%.2f%%)", static_cast<unsigned long long>(d->coverageDiffers),
              static_cast<unsigned long long>(d->coveredEither), 100.0 * d->coverageDiffersShare());
}

void TuningPanel::drawShaders() {
  if (ImGui::Button("Reload shaders (F5)")) viewer_.rebuildAndReloadShaders();
  if (ImGui::IsItemHovered())
    ImGui::SetTooltip("runs the build's shader target (glslang), then rebuilds every pipeline from the SPIR-V in %s",
                      engine::gpu::shaderDirectory().string().c_str());
  if (!viewer_.shaderReloadReport().empty()) ImGui::TextWrapped("%s", viewer_.shaderReloadReport().c_str());
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
    if (loaded && apply(*loaded)) viewer_.setStatusLine(fmt::format("loaded {}", settingsPath_.data()));
    else if (!loaded) viewer_.setStatusLine(loaded.error().message);
  }
  if (!viewer_.statusLine().empty()) ImGui::TextWrapped("%s", viewer_.statusLine().c_str());
}

// The glTF scene's cameras, when it has any: picking one looks through it until the camera moves.
void TuningPanel::drawSceneCameras() {
  const std::vector<std::string>& names = viewer_.sceneCameraNames();
  if (names.empty()) return;
  const bool through = viewer_.cameraMode() == CameraMode::Scene;
  const char* preview = through ? names[viewer_.sceneCamera()].c_str() : "(none)";
  if (!ImGui::BeginCombo("scene camera", preview)) return;
  for (std::size_t i = 0; i < names.size(); ++i) {
    ImGui::PushID(int(i));
    if (ImGui::Selectable(names[i].c_str(), through && viewer_.sceneCamera() == i)) {
      const engine::Status looked = viewer_.lookThroughSceneCamera(i);
      viewer_.setStatusLine(looked ? "looking through scene camera '" + names[i] + "'" : looked.error().message);
    }
    ImGui::PopID();
  }
  ImGui::EndCombo();
}

void TuningPanel::drawWindow() {
  int mode = int(viewer_.cameraMode());
  ImGui::TextUnformatted("camera");
  ImGui::SameLine();
  bool changed = ImGui::RadioButton("orbit", &mode, int(CameraMode::Orbit));
  ImGui::SameLine();
  changed |= ImGui::RadioButton("fly", &mode, int(CameraMode::Fly));
  if (changed) viewer_.setCameraMode(CameraMode(mode));
  drawSceneCameras();
  const char* help = "Orbit: left-drag rotates, right-drag or scroll zooms, middle-drag pans.";
  if (viewer_.cameraMode() == CameraMode::Fly) help = "Fly: W/A/S/D moves, Q/E down/up, Shift faster, right-drag looks.";
  if (viewer_.cameraMode() == CameraMode::Scene)
    help = "Scene camera: an orbit gesture (left-drag, scroll, middle-drag) or a fly one (W/A/S/D/Q/E, right-drag) "
           "leaves it from where it looks.";
  ImGui::TextWrapped("%s", help);
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
