#pragma once
// What the frame reads and what a user tunes, as typed values: the command line, a settings file,
// (later) the panel and test scripts all write one TuningState; Viewer::step applies it. Method
// and mode names exist only for parsing and printing.
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <string_view>

#include "engine/core/expected.h"
#include "hermite_sdf/renderable.h"

namespace samples {

// How the scene's meshes are drawn: as triangles, or baked into one SDF drawn by the paper's
// Hermite cells or one of the sphere-tracing baselines.
enum class Method { Mesh, Cells, Trilinear, Hermite };
const char* methodName(Method method);  // "mesh", "cells", "trilinear", "hermite"
std::optional<Method> parseMethod(std::string_view name);
bool isSdfMethod(Method method);

const char* normalModeName(hsdf::NormalMode mode);  // "exact", "central"
std::optional<hsdf::NormalMode> parseNormalMode(std::string_view name);

// DEBUG_VIEW_* of shaders/shared/host_device.h.
enum class DebugView : std::uint32_t { None = 0, Normals = 1, Depth = 2, Cells = 3, Evals = 4, Wireframe = 5 };
const char* debugViewName(DebugView view);  // "none", "normals", "depth", "cells", "evals", "wireframe"
std::optional<DebugView> parseDebugView(std::string_view name);

// Accepted ranges, shared by every writer of a TuningState.
struct IntRange {
  int min;
  int max;
};
inline constexpr IntRange kResolutionRange{2, 256};
inline constexpr IntRange kPaddingRange{0, 16};
inline constexpr IntRange kSubdivisionsRange{1, 64};
inline constexpr IntRange kRefineRange{0, 16};
// The panel's sliders: the useful part of each range (the paper uses n = 2 or 3; K past 256 is
// refused by the bake anyway).
inline constexpr IntRange kPanelResolutionRange{8, 256};
inline constexpr IntRange kPanelSubdivisionsRange{1, 16};
inline constexpr IntRange kPanelRefineRange{0, 4};

struct TuningState {
  Method method = Method::Cells;  // the paper's method is what a user sees first
  int resolution = 64;  // K samples per axis of the baked field (changing it re-bakes)
  int padding = 1;      // cells of padding around the mesh bounds (changing it re-bakes)
  std::uint32_t subdivisions = 3;
  std::uint32_t refineSteps = 1;
  hsdf::NormalMode normals = hsdf::NormalMode::Exact;
  bool fp16 = false;
  DebugView debugView = DebugView::None;
  bool frontToBack = true;  // cells: submit rows of cells front to back
  bool certified = false;   // cells: certified root search instead of n samples (renderable.h)

  bool operator==(const TuningState&) const = default;
};

// Ranges, and a resolution that leaves cells inside the padding. The message names the setting
// by its command-line option (--resolution).
engine::Status validateTuning(const TuningState& tuning);

// The one place tuning reaches the SDF component (method, n, refinement, normals, precision).
// Method::Mesh leaves the method as it is (the entity then is not drawn by the caller's choice).
void applyTuning(const TuningState& tuning, hsdf::HermiteSdfRenderable& renderable);

// Settings files: JSON objects with the keys "method", "resolution", "padding", "subdivisions",
// "refine", "normals", "fp16", "debug_view", "front_to_back", "certified", all optional. Loading starts from
// `base`; an unknown key, a value of the wrong type or out of range is refused naming the key
// and the file.
// One setting given as text, "key=value" style, with the keys and checks of a settings file (the
// value is read as JSON when it parses as a number or true/false, else as a name): how a --script
// line writes the TuningState. Errors name the key.
engine::Status setTuningValue(TuningState& tuning, std::string_view key, std::string_view value);

engine::Expected<TuningState> loadTuning(const std::filesystem::path& file, const TuningState& base = {});
engine::Status saveTuning(const std::filesystem::path& file, const TuningState& tuning);

}  // namespace samples
