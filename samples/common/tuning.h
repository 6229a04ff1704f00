#pragma once
// What the frame reads and what a user tunes, as typed values: the command line, a settings file,
// (later) the panel and test scripts all write one TuningState; Viewer::step applies it. Method
// and mode names exist only for parsing and printing.
#include <cstdint>
#include <filesystem>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "engine/core/expected.h"
#include "hermite_sdf/core/bake_job.h"
#include "hermite_sdf/render/cell_feature.h"
#include "hermite_sdf/render/renderable.h"
#include "hermite_sdf/render/scene_objects.h"
#include "hermite_sdf/render/sphere_trace_feature.h"
#include "shared/host_device.h"

namespace samples {

// How the scene's meshes are drawn: as triangles (Method::Mesh), or baked into one SDF drawn by one
// of the module's methods (the paper's Hermite cells, their runs and bricks, the sphere-tracing
// baselines). Not a second list of SDF methods: those and their names are hsdf::RenderMethod's
// (kRenderMethods, renderMethodName), and one converts to a Method, so that a method the module adds
// reaches the command line, the settings files and the panel without an edit here.
class Method {
 public:
  static const Method Mesh;  // the scene's triangles
  constexpr Method(hsdf::RenderMethod sdf) : sdf_(sdf) {}  // implicit: an SDF method is a Method
  // The SDF method; none for Mesh.
  constexpr std::optional<hsdf::RenderMethod> sdf() const { return sdf_; }
  constexpr bool operator==(const Method&) const = default;

 private:
  constexpr Method() = default;  // Mesh
  std::optional<hsdf::RenderMethod> sdf_;
};
inline constexpr Method Method::Mesh{};

// Mesh, then the module's methods in their order (the order of --help and of the panel).
std::vector<Method> allMethods();
const char* methodName(Method method);  // "mesh", else hsdf::renderMethodName
std::string allMethodNames();            // "mesh, cells, trilinear, ...", for messages
std::optional<Method> parseMethod(std::string_view name);
bool isSdfMethod(Method method);
// The cell renderers (hsdf::drawsCells; not Mesh): they draw the baked asset's kept cells.
bool drawsCells(Method method);
// The sphere tracers (trilinear, hermite): they need the dense field.
bool needsDenseField(Method method);

const char* normalModeName(hsdf::NormalMode mode);  // "exact", "central"
std::optional<hsdf::NormalMode> parseNormalMode(std::string_view name);

// A DEBUG_VIEW_* of shaders/shared/host_device.h, typed (DebugView(DEBUG_VIEW_NORMALS)): the views,
// their numbers and names (shader::kDebugViewNames) are defined there once, for GLSL and C++.
enum class DebugView : std::uint32_t {};
std::vector<DebugView> allDebugViews();     // by value
const char* debugViewName(DebugView view);  // "none", "normals", "depth", "cells", "evals", "wireframe"
std::optional<DebugView> parseDebugView(std::string_view name);

// The cells' three-way switches (early depth stage, thin boxes, tiles): the module's one type,
// hsdf::AutoSwitch, where Auto lets the device decide (each TuningState member says how). A settings
// file writes one as true, false or "auto", the command line as auto, on or off.
using AutoSwitch = hsdf::AutoSwitch;
const char* autoSwitchName(AutoSwitch mode);  // "auto", "on", "off"
std::optional<AutoSwitch> parseAutoSwitch(std::string_view name);

// Split-screen comparison: off, or a divider that is vertical (compared method on the right) or
// horizontal (compared method at the bottom).
enum class SplitMode { Off, Vertical, Horizontal };
const char* splitModeName(SplitMode mode);  // "off", "vertical", "horizontal"
std::optional<SplitMode> parseSplitMode(std::string_view name);

// Accepted ranges, shared by every writer of a TuningState.
struct IntRange {
  int min;
  int max;
};
// K, by method (resolutionRange): the cell renderers up to 2048, past the dense bake's reach with
// the sparse bake (bakeBandFor; the bake budget may still refuse a large K, naming its limit); the
// dense tracers up to 512, where their textures hold K^3 texels (the Hermite one 16 B a texel: 2 GiB)
// and the dense bake K^3 samples. kResolutionRange is the cells' and the widest (what a file may hold).
inline constexpr IntRange kResolutionRange{2, 2048};
inline constexpr IntRange kDenseResolutionRange{2, 512};
// Past this K the cell renderers bake sparse (no dense field, so a switch to a dense tracer re-bakes).
inline constexpr int kDenseBakeMaxResolution = 256;
// The compared side's default K (2K) stops here: a dense bake past it takes minutes.
inline constexpr int kDefaultCompareResolutionMax = 256;
inline constexpr IntRange kPaddingRange{hsdf::kMinBakePadding, 16};
inline constexpr IntRange kSubdivisionsRange{1, 64};
inline constexpr IntRange kRefineRange{0, 16};
// The panel's sliders: the useful part of each range (the paper uses n = 2 or 3; K past 256 is
// beyond the method's range is refused).
inline constexpr IntRange kPanelResolutionRange{8, 2048};
// Levels of detail: the target size of a drawn cell in pixels (hsdf::HermiteSdfLod::pixelsPerCell).
struct FloatRange {
  float min;
  float max;
};
// A shell's thickness in the scene's units (0: the solid the meshes bound); the top is any scene's.
inline constexpr FloatRange kShellThicknessRange{0.0f, 1e6f};
inline constexpr FloatRange kLodPixelsPerCellRange{0.25f, 64.0f};
inline constexpr FloatRange kSplitPositionRange{0.05f, 0.95f};  // both sides stay visible
inline constexpr FloatRange kTraceEpsilonRange{1e-6f, 0.1f};
inline constexpr IntRange kTraceMaxStepsRange{1, 4096};
inline constexpr FloatRange kCentralDifferenceStepRange{0.01f, 1.0f};
inline constexpr IntRange kMaxRunLengthRange{1, 64};
inline constexpr IntRange kUploadMiBPerFrameRange{0, 4096};  // 0: no limit
inline constexpr const auto& kTileSizes = hsdf::HermiteCellFeature::kTileSizes;
inline constexpr IntRange kPanelSubdivisionsRange{1, 16};
inline constexpr IntRange kPanelRefineRange{0, 4};

struct TuningState {
  Method method = hsdf::RenderMethod::Cells;  // the paper's method is what a user sees first
  int resolution = 64;  // K samples per axis of the baked field (changing it re-bakes)
  int padding = 1;      // cells of padding around the mesh bounds (changing it re-bakes)
  // Above 0: the meshes baked as shells this thick around their triangles, in the scene's units
  // (hsdf::BakeSettings::shellThickness), for sheets and open surfaces (changing it re-bakes).
  float shellThickness = 0.0f;
  std::uint32_t subdivisions = 3;
  std::uint32_t refineSteps = 1;
  hsdf::NormalMode normals = hsdf::NormalMode::Exact;
  bool fp16 = false;
  DebugView debugView = DebugView(DEBUG_VIEW_NONE);
  bool frontToBack = true;  // cells: submit rows of cells front to back
  AutoSwitch earlyDepth = AutoSwitch::Auto;  // cells: test boxes at their faces' depth, hidden ones skip the search
  bool certified = false;   // cells: certified root search instead of n samples (renderable.h)
  bool cullBricks = true;   // cell bricks: the GPU culling pass (frustum, normal cones) before the prepass
  bool cullCells = true;    // cells: the same pass per cell (each with its own normal cone)
  bool cullOcclusion = hsdf::HermiteCellFeature::Settings{}.cullOcclusion;  // cells (with cullCells): two-phase occlusion culling against the depth pyramid
  bool proxyBoxes = hsdf::HermiteCellFeature::Settings{}.proxyBoxes;  // cells, runs, bricks: each cell drawn and searched over the part that can hold its roots
  AutoSwitch thinBoxes = AutoSwitch::Auto;  // cells: 12 bytes of varyings per box, records read by address
  AutoSwitch tiles = AutoSwitch::Auto;      // cells (with cullCells): the kept cells binned into screen tiles, not a box per cell
  std::uint32_t tileSize = hsdf::HermiteCellFeature::Settings{}.tileSize;  // tiles: their side in pixels, 4, 8 or 16
  // Split-screen comparison (same camera, same frame): the tuning above on one side, the compared
  // method on the other, drawn from its own bake at compareResolution with compareNormals (n,
  // refinement and fp16 are shared). A compared method of cells draws the main asset (K above).
  SplitMode split = SplitMode::Off;
  float splitPosition = 0.5f;  // the divider, as a fraction of the width (vertical) or height
  Method compareMethod = hsdf::RenderMethod::TrilinearSphereTrace;
  // 0: twice K, at most kDefaultCompareResolutionMax (the paper's rule of thumb for trilinear).
  int compareResolution = 0;
  hsdf::NormalMode compareNormals = hsdf::NormalMode::CentralDifferences;  // the paper's for trilinear
  // Difference view: per pixel, the angle between the two methods' normals as a heat map with a
  // legend, and the share of pixels that one method covers and the other does not.
  bool difference = false;
  // A glTF scene loaded as separate objects (SceneDesc::objects; read when it loads): how nodes
  // without an extras choice draw, and nodes drawn as triangles whatever their extras say
  // (hermite_sdf/render/scene_objects.h).
  hsdf::NodeDraw nodeDraw = hsdf::NodeDraw::Sdf;
  std::vector<std::string> triangleNodes;
  // Levels of detail (hsdf::HermiteSdfLod): the baked object also at K/2, K/4, ... (down to K = 16),
  // each frame drawing the coarsest level whose cells cover at most lodPixelsPerCell pixels.
  bool lod = false;
  float lodPixelsPerCell = 2.0f;
  // The sphere tracers (trilinear, dense Hermite): stop when |f| < traceEpsilon grid spacings, give
  // up after traceMaxSteps evaluations (counted as out of steps), central differences (NormalMode::
  // CentralDifferences) centralDifferenceStep spacings apart. Defaults: the feature's.
  float traceEpsilon = hsdf::SphereTraceFeature::Settings{}.epsilon;
  std::uint32_t traceMaxSteps = hsdf::SphereTraceFeature::Settings{}.maxSteps;
  float centralDifferenceStep = hsdf::SphereTraceFeature::Settings{}.centralDifferenceStep;
  // Cell runs: the most cells one run's box covers (HermiteCellFeature::Settings::maxRunLength).
  std::uint32_t maxRunLength = hsdf::HermiteCellFeature::Settings{}.maxRunLength;
  // Cells: the MiB of cell records one frame uploads when a new asset comes, 0 for no limit
  // (HermiteCellFeature::Settings::uploadBytesPerFrame; headless viewers upload without one).
  std::uint32_t uploadMiBPerFrame = std::uint32_t(hsdf::HermiteCellFeature::Settings{}.uploadBytesPerFrame >> 20);

  bool operator==(const TuningState&) const = default;
};

// The keys of a settings file and of --script settings are the table's (tuning_fields.h).
bool isTuningKey(std::string_view key);
std::string tuningKeyList();  // "method, resolution, ..."

// The settings of the tuning that make one bake differ from another (K, padding, shell): the field
// drawn, the one being baked and the one asked for are compared as keys, and a failed bake puts the
// tuning back to the key drawn.
struct BakeKey {
  int resolution = 0;
  int padding = 0;
  float shellThickness = 0.0f;
  bool operator==(const BakeKey&) const = default;
};
BakeKey bakeKey(const TuningState& tuning);  // the main side's (the compared side's: of compareTuning)
BakeKey bakeKey(const hsdf::BakeSettings& settings);
void setBakeKey(const BakeKey& key, hsdf::BakeSettings& settings);
void setBakeKey(const BakeKey& key, TuningState& tuning);

// The K range of a method (Mesh: the cells', as the SDF is baked when an SDF method is picked).
IntRange resolutionRange(Method method);
// How the bake for `method` at K runs: Dense while every method can draw the result (K up to
// kDenseBakeMaxResolution, or a dense tracer), Sparse for the cell renderers past it (the same
// cells: sparse_bake.h; open meshes excepted, as with the narrow band).
hsdf::BakeBand bakeBandFor(Method method, int resolution);

// Ranges (the resolution's by method, naming the limit), and a resolution that leaves cells inside
// the padding. The message names the setting by its command-line option (--resolution).
engine::Status validateTuning(const TuningState& tuning);

// The K the compared side is drawn with: compareResolution, or 2K capped at the range's top.
int effectiveCompareResolution(const TuningState& tuning);
// Whether the frame compares two methods (split screen or difference view).
bool comparing(const TuningState& tuning);
// The tuning of the compared side: the main tuning with the compared method, K and normals.
TuningState compareTuning(const TuningState& tuning);

// The method that draws `asset` for `wanted`: a sphere tracer needs the dense field, so an asset of
// cells only (a sparse bake whose dense re-bake is still running, a cells-only .hsdf) draws its
// cells instead of failing the frame.
hsdf::RenderMethod drawableMethod(hsdf::RenderMethod wanted, const hsdf::SdfAsset* asset);
// The one place tuning reaches the SDF component (method, n, refinement, normals, precision).
// Method::Mesh leaves the method as it is (the entity then is not drawn by the caller's choice).
void applyTuning(const TuningState& tuning, hsdf::HermiteSdfRenderable& renderable);
// The one place tuning reaches the render features' settings (cells: order, culling, thin boxes,
// tiles, early depth; tracers: epsilon, steps, central step): the Viewer's renderer, and the perf
// capture's measuring renderer, which must draw a row as its frames were drawn.
void applyTuning(const TuningState& tuning, hsdf::HermiteCellFeature::Settings& cells,
                 hsdf::SphereTraceFeature::Settings& tracers);
// After applyTuning, for frames that are captured (a headless viewer's: screenshots, perf captures,
// tests; the capture's measuring renderer): each draws whole assets, never the object an asset
// uploaded in parts replaces, and no pipeline warmer compiles beside them (warming serves a user's
// next switch; here it would take CPU from the frames measured, and on lavapipe its pipelines
// still being compiled grew a soak's RSS between two samples of one state).
void applyCapturedFrames(hsdf::HermiteCellFeature::Settings& cells, hsdf::SphereTraceFeature::Settings& tracers);

// Settings files: JSON objects whose keys are the table's (tuning_fields.h, each with its kind of
// value and its range), all optional. Loading starts from `base`; an unknown key, a value of the
// wrong type or out of range is refused naming the key and the file.
// Settings given as text, "key=value" style, with the keys and checks of a settings file (the
// value is read as JSON when it parses as a number or true/false, else as a name): how a --script
// line writes the TuningState. The values are checked together, after all are read, as a settings
// file's: "padding=16 resolution=40" from K = 16 passes as "resolution=40 padding=16" does. Errors
// name the key; on an error `tuning` is unchanged.
struct TuningAssignment {
  std::string_view key;
  std::string_view value;
};
engine::Status setTuningValues(TuningState& tuning, std::span<const TuningAssignment> values);
engine::Status setTuningValue(TuningState& tuning, std::string_view key, std::string_view value);

engine::Expected<TuningState> loadTuning(const std::filesystem::path& file, const TuningState& base = {});
engine::Status saveTuning(const std::filesystem::path& file, const TuningState& tuning);

}  // namespace samples
