#include "tuning.h"

#include <algorithm>
#include <array>
#include <utility>

#include <fmt/format.h>
#include <fmt/ranges.h>
#include <nlohmann/json.hpp>

#include "engine/core/files.h"
#include "shared/host_device.h"

namespace samples {
namespace {

template <class T, std::size_t N>
using NameTable = std::array<std::pair<T, const char*>, N>;

constexpr const char* kMeshName = "mesh";  // the one name not the module's
constexpr NameTable<hsdf::NormalMode, 2> kNormalModes{
    {{hsdf::NormalMode::Exact, "exact"}, {hsdf::NormalMode::CentralDifferences, "central"}}};
constexpr NameTable<SplitMode, 3> kSplitModes{
    {{SplitMode::Off, "off"}, {SplitMode::Vertical, "vertical"}, {SplitMode::Horizontal, "horizontal"}}};
constexpr NameTable<EarlyDepth, 3> kEarlyDepths{
    {{EarlyDepth::Auto, "auto"}, {EarlyDepth::On, "on"}, {EarlyDepth::Off, "off"}}};
constexpr float kSplitMin = 0.05f, kSplitMax = 0.95f;  // both sides stay visible
template <class T, std::size_t N>
const char* nameOf(const NameTable<T, N>& table, T value) {
  for (const auto& [v, name] : table)
    if (v == value) return name;
  return "?";
}

template <class T, std::size_t N>
std::optional<T> valueOf(const NameTable<T, N>& table, std::string_view name) {
  for (const auto& [v, n] : table)
    if (name == n) return v;
  return std::nullopt;
}

template <class T, std::size_t N>
std::string allNames(const NameTable<T, N>& table) {
  std::string names;
  for (const auto& entry : table) names += (names.empty() ? "" : ", ") + std::string(entry.second);
  return names;
}

engine::Status checkRange(const char* option, long long value, IntRange range) {
  if (value >= range.min && value <= range.max) return {};
  return engine::makeError(fmt::format("{} {} is outside {}..{}", option, value, range.min, range.max));
}

engine::Status checkFloatRange(const char* option, float value, FloatRange range) {
  if (value >= range.min && value <= range.max) return {};  // false for NaN
  return engine::makeError(fmt::format("{} {} is outside {}..{}", option, value, range.min, range.max));
}

// One key of a settings file: reads it into `out` or says what is wrong with the value.
using json = nlohmann::json;

engine::Status readInt(const json& value, IntRange range, int& out) {
  if (!value.is_number_integer()) return engine::makeError(fmt::format("expected an integer, got {}", value.dump()));
  const long long v = value.get<long long>();
  if (v < range.min || v > range.max)
    return engine::makeError(fmt::format("{} is outside {}..{}", v, range.min, range.max));
  out = int(v);
  return {};
}

engine::Status readFloat(const json& value, float lo, float hi, float& out) {
  if (!value.is_number()) return engine::makeError(fmt::format("expected a number, got {}", value.dump()));
  // Compared as the float it is stored as: the bounds are floats, and 0.05 written in a file is a
  // hair below 0.05f as a double, so a bound the message names would be refused.
  const double v = value.get<double>();
  const float f = float(v);
  if (!(f >= lo && f <= hi)) return engine::makeError(fmt::format("{} is outside {}..{}", v, lo, hi));
  out = f;
  return {};
}

engine::Status readBool(const json& value, bool& out) {
  if (!value.is_boolean()) return engine::makeError(fmt::format("expected true or false, got {}", value.dump()));
  out = value.get<bool>();
  return {};
}

// true (on), false (off) or "auto" (the device decides: on for software rasterizers).
engine::Status readEarlyDepth(const json& value, EarlyDepth& out) {
  if (value.is_boolean()) {
    out = value.get<bool>() ? EarlyDepth::On : EarlyDepth::Off;
    return {};
  }
  if (value.is_string() && value.get<std::string>() == "auto") {
    out = EarlyDepth::Auto;
    return {};
  }
  return engine::makeError(fmt::format("expected true, false or \"auto\", got {}", value.dump()));
}

engine::Status refuseName(const json& value, const std::string& names) {
  return engine::makeError(fmt::format("{} is not one of {}", value.dump(), names));
}

template <class T, std::size_t N>
engine::Status readName(const json& value, const NameTable<T, N>& table, T& out) {
  const std::optional<T> parsed = value.is_string() ? valueOf(table, value.get<std::string>()) : std::nullopt;
  if (!parsed) return refuseName(value, allNames(table));
  out = *parsed;
  return {};
}

// A name of a list that is not a NameTable here (the methods, the debug views: defined by the module
// and the shared header).
template <class T>
engine::Status readParsed(const json& value, std::optional<T> (*parse)(std::string_view), const std::string& names,
                          T& out) {
  const std::optional<T> parsed = value.is_string() ? parse(value.get<std::string>()) : std::nullopt;
  if (!parsed) return refuseName(value, names);
  out = *parsed;
  return {};
}

engine::Status readMethod(const json& value, Method& out) { return readParsed(value, parseMethod, allMethodNames(), out); }

engine::Status readDebugView(const json& value, DebugView& out) {
  std::string names;
  for (const char* name : shader::kDebugViewNames) names += (names.empty() ? "" : ", ") + std::string(name);
  return readParsed(value, parseDebugView, names, out);
}

engine::Status readNodeDraw(const json& value, hsdf::NodeDraw& out) {
  const auto parsed = value.is_string() ? hsdf::parseNodeDraw(value.get<std::string>()) : std::nullopt;
  if (!parsed) return engine::makeError(fmt::format("{} is not one of sdf, triangles", value.dump()));
  out = *parsed;
  return {};
}

// An array of names, or (a --script line, a command-line option) one string of names separated by
// commas. An empty name is refused: it would match only unnamed nodes.
engine::Status readNames(const json& value, std::vector<std::string>& out) {
  std::vector<std::string> names;
  if (value.is_string()) {
    const std::string text = value.get<std::string>();
    for (std::size_t start = 0, end = 0; end != std::string::npos; start = end + 1) {
      end = text.find(',', start);
      names.push_back(text.substr(start, end == std::string::npos ? end : end - start));
    }
    if (text.empty()) names.clear();
  } else if (value.is_array()) {
    for (const json& name : value) {
      if (!name.is_string()) return engine::makeError(fmt::format("expected node names, got {}", name.dump()));
      names.push_back(name.get<std::string>());
    }
  } else {
    return engine::makeError(fmt::format("expected an array of node names, got {}", value.dump()));
  }
  if (std::find(names.begin(), names.end(), std::string()) != names.end())
    return engine::makeError("an empty node name");
  out = std::move(names);
  return {};
}

engine::Status readKey(const std::string& key, const json& value, TuningState& t) {
  int n = 0;
  if (key == "method") return readMethod(value, t.method);
  if (key == "resolution") return readInt(value, kResolutionRange, t.resolution);
  if (key == "padding") return readInt(value, kPaddingRange, t.padding);
  if (key == "subdivisions") {
    ENGINE_TRY(readInt(value, kSubdivisionsRange, n));
    t.subdivisions = std::uint32_t(n);
    return {};
  }
  if (key == "refine") {
    ENGINE_TRY(readInt(value, kRefineRange, n));
    t.refineSteps = std::uint32_t(n);
    return {};
  }
  if (key == "normals") return readName(value, kNormalModes, t.normals);
  if (key == "fp16") return readBool(value, t.fp16);
  if (key == "debug_view") return readDebugView(value, t.debugView);
  if (key == "front_to_back") return readBool(value, t.frontToBack);
  if (key == "early_depth") return readEarlyDepth(value, t.earlyDepth);
  if (key == "certified") return readBool(value, t.certified);
  if (key == "cull_bricks") return readBool(value, t.cullBricks);
  if (key == "cull_cells") return readBool(value, t.cullCells);
  if (key == "cull_occlusion") return readBool(value, t.cullOcclusion);
  if (key == "proxy_boxes") return readBool(value, t.proxyBoxes);
  if (key == "thin_boxes") return readEarlyDepth(value, t.thinBoxes);  // the same true / false / "auto" switch
  if (key == "tiles") return readEarlyDepth(value, t.tiles);
  if (key == "tile_size") {
    ENGINE_TRY(readInt(value, IntRange{4, 16}, n));
    t.tileSize = std::uint32_t(n);
    return {};  // one of kTileSizes: validateTuning
  }
  if (key == "split") return readName(value, kSplitModes, t.split);
  if (key == "split_position") return readFloat(value, kSplitMin, kSplitMax, t.splitPosition);
  if (key == "compare_method") {
    ENGINE_TRY(readMethod(value, t.compareMethod));
    if (!isSdfMethod(t.compareMethod)) return engine::makeError("the compared method must be an SDF method (cells, cells-runs, cell-bricks, trilinear, hermite)");
    return {};
  }
  if (key == "compare_resolution") {
    if (value.is_number_integer() && value.get<long long>() == 0) {
      t.compareResolution = 0;
      return {};
    }
    return readInt(value, kResolutionRange, t.compareResolution);
  }
  if (key == "compare_normals") return readName(value, kNormalModes, t.compareNormals);
  if (key == "difference") return readBool(value, t.difference);
  if (key == "node_draw") return readNodeDraw(value, t.nodeDraw);
  if (key == "triangle_nodes") return readNames(value, t.triangleNodes);
  if (key == "lod") return readBool(value, t.lod);
  if (key == "lod_pixels_per_cell")
    return readFloat(value, kLodPixelsPerCellRange.min, kLodPixelsPerCellRange.max, t.lodPixelsPerCell);
  if (key == "trace_epsilon") return readFloat(value, kTraceEpsilonRange.min, kTraceEpsilonRange.max, t.traceEpsilon);
  if (key == "trace_max_steps") {
    ENGINE_TRY(readInt(value, kTraceMaxStepsRange, n));
    t.traceMaxSteps = std::uint32_t(n);
    return {};
  }
  if (key == "central_difference_step")
    return readFloat(value, kCentralDifferenceStepRange.min, kCentralDifferenceStepRange.max, t.centralDifferenceStep);
  if (key == "max_run_length") {
    ENGINE_TRY(readInt(value, kMaxRunLengthRange, n));
    t.maxRunLength = std::uint32_t(n);
    return {};
  }
  return engine::makeError("unknown setting (known: " + tuningKeyList() + ")");
}

}  // namespace

std::vector<Method> allMethods() {
  std::vector<Method> methods{Method::Mesh};
  methods.insert(methods.end(), std::begin(hsdf::kRenderMethods), std::end(hsdf::kRenderMethods));
  return methods;
}
std::string allMethodNames() {
  std::string names;
  for (const Method method : allMethods()) names += (names.empty() ? "" : ", ") + std::string(methodName(method));
  return names;
}

const char* methodName(Method method) { return method.sdf() ? hsdf::renderMethodName(*method.sdf()) : kMeshName; }
const char* earlyDepthName(EarlyDepth mode) { return nameOf(kEarlyDepths, mode); }
std::optional<EarlyDepth> parseEarlyDepth(std::string_view name) { return valueOf(kEarlyDepths, name); }
const char* splitModeName(SplitMode mode) { return nameOf(kSplitModes, mode); }
std::optional<SplitMode> parseSplitMode(std::string_view name) { return valueOf(kSplitModes, name); }

std::string tuningKeyList() {
  std::string list;
  for (std::string_view key : kTuningKeys) list += (list.empty() ? "" : ", ") + std::string(key);
  return list;
}

int effectiveCompareResolution(const TuningState& t) {
  return t.compareResolution > 0 ? t.compareResolution : std::min(2 * t.resolution, kDefaultCompareResolutionMax);
}

bool comparing(const TuningState& t) { return t.split != SplitMode::Off || t.difference; }

TuningState compareTuning(const TuningState& t) {
  TuningState compared = t;
  compared.method = t.compareMethod;
  compared.resolution = drawsCells(t.compareMethod) ? t.resolution : effectiveCompareResolution(t);
  compared.normals = t.compareNormals;
  return compared;
}
std::optional<Method> parseMethod(std::string_view name) {
  if (name == kMeshName) return Method::Mesh;
  const std::optional<hsdf::RenderMethod> sdf = hsdf::parseRenderMethod(name);
  return sdf ? std::optional<Method>(*sdf) : std::nullopt;
}
bool isSdfMethod(Method method) { return method.sdf().has_value(); }
bool drawsCells(Method method) { return method.sdf() && hsdf::drawsCells(*method.sdf()); }

bool needsDenseField(Method method) { return isSdfMethod(method) && !drawsCells(method); }
const char* normalModeName(hsdf::NormalMode mode) { return nameOf(kNormalModes, mode); }
std::optional<hsdf::NormalMode> parseNormalMode(std::string_view name) { return valueOf(kNormalModes, name); }
std::vector<DebugView> allDebugViews() {
  std::vector<DebugView> views;
  for (std::uint32_t v = 0; v < std::size(shader::kDebugViewNames); ++v) views.push_back(DebugView(v));
  return views;
}
const char* debugViewName(DebugView view) {
  const auto v = std::uint32_t(view);
  return v < std::size(shader::kDebugViewNames) ? shader::kDebugViewNames[v] : "?";
}
std::optional<DebugView> parseDebugView(std::string_view name) {
  for (const DebugView view : allDebugViews())
    if (name == debugViewName(view)) return view;
  return std::nullopt;
}

IntRange resolutionRange(Method method) { return drawsCells(method) || method == Method::Mesh ? kResolutionRange : kDenseResolutionRange; }

hsdf::BakeBand bakeBandFor(Method method, int resolution) {
  return drawsCells(method) && resolution > kDenseBakeMaxResolution ? hsdf::BakeBand::Sparse : hsdf::BakeBand::Dense;
}

namespace {

// The K range of the method, the limit named with why it is there.
engine::Status checkResolution(Method method, int resolution) {
  const IntRange range = resolutionRange(method);
  if (resolution >= range.min && resolution <= range.max) return {};
  const char* why = drawsCells(method) || method == Method::Mesh
                        ? "the cells' limit (sparse bake; the bake budget may refuse less)"
                        : "the dense tracers' limit (K^3 texels: the Hermite texture is 2 GiB at K = 512)";
  return engine::makeError(fmt::format("--resolution {} is outside {}..{} for --method {}: {}", resolution, range.min,
                                       range.max, methodName(method), why));
}

}  // namespace

engine::Status validateTuning(const TuningState& t) {
  ENGINE_TRY(checkResolution(t.method, t.resolution));
  ENGINE_TRY(checkRange("--padding", t.padding, kPaddingRange));
  ENGINE_TRY(checkRange("--subdivisions", t.subdivisions, kSubdivisionsRange));
  ENGINE_TRY(checkRange("--refine", t.refineSteps, kRefineRange));
  if (t.compareResolution != 0)
    ENGINE_TRY(checkRange("--compare-resolution", t.compareResolution, resolutionRange(t.compareMethod)));
  ENGINE_TRY(checkFloatRange("--lod-pixels-per-cell", t.lodPixelsPerCell, kLodPixelsPerCellRange));
  ENGINE_TRY(checkFloatRange("--trace-epsilon", t.traceEpsilon, kTraceEpsilonRange));
  ENGINE_TRY(checkRange("--trace-max-steps", t.traceMaxSteps, kTraceMaxStepsRange));
  ENGINE_TRY(checkFloatRange("--central-difference-step", t.centralDifferenceStep, kCentralDifferenceStepRange));
  ENGINE_TRY(checkRange("--max-run-length", t.maxRunLength, kMaxRunLengthRange));
  if (!hsdf::HermiteCellFeature::tileSizeValid(t.tileSize))
    return engine::makeError(fmt::format("--tile-size {} is not one of {}", t.tileSize, fmt::join(kTileSizes, ", ")));
  if (!isSdfMethod(t.compareMethod))
    return engine::makeError("--compare-method mesh: the compared method must be cells, trilinear or hermite");
  ENGINE_TRY(checkFloatRange("--split-position", t.splitPosition, FloatRange{kSplitMin, kSplitMax}));
  if (t.resolution - 1 - 2 * t.padding < 1)
    return engine::makeError(
        fmt::format("--resolution {} leaves no cells inside --padding {}", t.resolution, t.padding));
  // The compared side's K only where it is drawn or was asked for: the automatic 2K (at most
  // 256) is never below a K that passed.
  const int compareK = effectiveCompareResolution(t);
  if ((comparing(t) || t.compareResolution != 0) && compareK - 1 - 2 * t.padding < 1)
    return engine::makeError(
        fmt::format("--compare-resolution {} leaves no cells inside --padding {}", compareK, t.padding));
  if (std::find(t.triangleNodes.begin(), t.triangleNodes.end(), std::string()) != t.triangleNodes.end())
    return engine::makeError("--triangle-nodes: an empty node name");
  return {};
}

hsdf::RenderMethod drawableMethod(hsdf::RenderMethod wanted, const hsdf::SdfAsset* asset) {
  return needsDenseField(wanted) && asset && asset->field.samples.empty() ? hsdf::RenderMethod::Cells : wanted;
}

void applyTuning(const TuningState& tuning, hsdf::HermiteSdfRenderable& renderable) {
  if (tuning.method.sdf()) renderable.method = drawableMethod(*tuning.method.sdf(), renderable.asset.get());
  renderable.subdivisions = tuning.subdivisions;
  renderable.refineSteps = tuning.refineSteps;
  renderable.normals = tuning.normals;
  renderable.halfPrecision = tuning.fp16;
  renderable.certified = tuning.certified;
}

namespace {

template <typename Switch>
Switch threeWay(EarlyDepth mode) {
  return mode == EarlyDepth::On ? Switch::On : mode == EarlyDepth::Off ? Switch::Off : Switch::Auto;
}

}  // namespace

void applyTuning(const TuningState& tuning, hsdf::HermiteCellFeature::Settings& cells,
                 hsdf::SphereTraceFeature::Settings& tracers) {
  cells.frontToBack = tuning.frontToBack;
  cells.maxRunLength = tuning.maxRunLength;
  cells.cullBricks = tuning.cullBricks;
  cells.cullCells = tuning.cullCells;
  cells.cullOcclusion = tuning.cullOcclusion;
  cells.proxyBoxes = tuning.proxyBoxes;
  cells.thinBoxes = threeWay<hsdf::HermiteCellFeature::ThinBoxes>(tuning.thinBoxes);
  cells.tiles = threeWay<hsdf::HermiteCellFeature::Tiles>(tuning.tiles);
  cells.tileSize = tuning.tileSize;
  cells.earlyDepth = threeWay<hsdf::HermiteCellFeature::EarlyDepth>(tuning.earlyDepth);
  tracers.epsilon = tuning.traceEpsilon;
  tracers.maxSteps = tuning.traceMaxSteps;
  tracers.centralDifferenceStep = tuning.centralDifferenceStep;
}

engine::Status setTuningValues(TuningState& tuning, std::span<const TuningAssignment> values) {
  TuningState changed = tuning;
  for (const auto& [key, value] : values) {
    json parsed = json::parse(value, nullptr, /*allow_exceptions=*/false);
    if (parsed.is_discarded() || !(parsed.is_number() || parsed.is_boolean())) parsed = std::string(value);
    ENGINE_TRY(readKey(std::string(key), parsed, changed).withContext(fmt::format("setting '{}'", key)));
  }
  ENGINE_TRY(validateTuning(changed));
  tuning = changed;
  return {};
}

engine::Status setTuningValue(TuningState& tuning, std::string_view key, std::string_view value) {
  const TuningAssignment one{key, value};
  return setTuningValues(tuning, std::span(&one, 1));
}

engine::Expected<TuningState> loadTuning(const std::filesystem::path& file, const TuningState& base) {
  ENGINE_TRY_ASSIGN(std::string text, engine::readTextFile(file));
  const json root = json::parse(text, nullptr, /*allow_exceptions=*/false);
  if (root.is_discarded()) return engine::makeError(file.string() + ": not valid JSON");
  if (!root.is_object()) return engine::makeError(file.string() + ": expected a JSON object of settings");
  TuningState tuning = base;
  for (const auto& [key, value] : root.items())
    ENGINE_TRY(readKey(key, value, tuning).withContext(fmt::format("{}: setting '{}'", file.string(), key)));
  ENGINE_TRY(validateTuning(tuning).withContext(file.string()));
  return tuning;
}

engine::Status saveTuning(const std::filesystem::path& file, const TuningState& t) {
  const json earlyDepth = t.earlyDepth == EarlyDepth::Auto ? json("auto") : json(t.earlyDepth == EarlyDepth::On);
  const json root = {{"method", methodName(t.method)},
                     {"resolution", t.resolution},
                     {"padding", t.padding},
                     {"subdivisions", t.subdivisions},
                     {"refine", t.refineSteps},
                     {"normals", normalModeName(t.normals)},
                     {"fp16", t.fp16},
                     {"debug_view", debugViewName(t.debugView)},
                     {"front_to_back", t.frontToBack},
                     {"early_depth", earlyDepth},
                     {"certified", t.certified},
                     {"cull_bricks", t.cullBricks},
                     {"cull_cells", t.cullCells},
                     {"cull_occlusion", t.cullOcclusion},
                     {"proxy_boxes", t.proxyBoxes},
                     {"thin_boxes", t.thinBoxes == ThinBoxes::Auto ? json("auto") : json(t.thinBoxes == ThinBoxes::On)},
                     {"tiles", t.tiles == TiledCells::Auto ? json("auto") : json(t.tiles == TiledCells::On)},
                     {"tile_size", t.tileSize},
                     {"split", splitModeName(t.split)},
                     {"split_position", t.splitPosition},
                     {"compare_method", methodName(t.compareMethod)},
                     {"compare_resolution", t.compareResolution},
                     {"compare_normals", normalModeName(t.compareNormals)},
                     {"difference", t.difference},
                     {"node_draw", hsdf::nodeDrawName(t.nodeDraw)},
                     {"triangle_nodes", t.triangleNodes},
                     {"lod", t.lod},
                     {"lod_pixels_per_cell", t.lodPixelsPerCell},
                     {"trace_epsilon", t.traceEpsilon},
                     {"trace_max_steps", t.traceMaxSteps},
                     {"central_difference_step", t.centralDifferenceStep},
                     {"max_run_length", t.maxRunLength}};
  return engine::writeTextFile(file, root.dump(2) + "\n");
}

}  // namespace samples
