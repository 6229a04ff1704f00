#include "tuning_fields.h"

#include <algorithm>
#include <array>
#include <cstdio>
#include <cstdlib>
#include <type_traits>
#include <utility>

#include <fmt/format.h>
#include <fmt/ranges.h>
#include <nlohmann/json.hpp>

#include "engine/core/files.h"

namespace samples {
namespace {

using json = nlohmann::json;

template <class T, std::size_t N>
using NameTable = std::array<std::pair<T, const char*>, N>;

constexpr NameTable<hsdf::NormalMode, 2> kNormalModes{
    {{hsdf::NormalMode::Exact, "exact"}, {hsdf::NormalMode::CentralDifferences, "central"}}};
constexpr NameTable<SplitMode, 3> kSplitModes{
    {{SplitMode::Off, "off"}, {SplitMode::Vertical, "vertical"}, {SplitMode::Horizontal, "horizontal"}}};
constexpr NameTable<AutoSwitch, 3> kAutoSwitches{
    {{AutoSwitch::Auto, "auto"}, {AutoSwitch::On, "on"}, {AutoSwitch::Off, "off"}}};
constexpr NameTable<hsdf::NodeDraw, 2> kNodeDraws{{{hsdf::NodeDraw::Sdf, "sdf"}, {hsdf::NodeDraw::Triangles, "triangles"}}};

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
std::vector<T> valuesOf(const NameTable<T, N>& table) {
  std::vector<T> values;
  for (const auto& entry : table) values.push_back(entry.first);
  return values;
}

// Each kind of name (a member type of TuningMember): its values in their order, their names and the
// parser, so that reading, writing, the command line and the panel treat every kind alike.
template <class T>
struct Named;
template <>
struct Named<Method> {
  static std::vector<Method> all() { return allMethods(); }
  static const char* name(Method m) { return methodName(m); }
  static std::optional<Method> parse(std::string_view n) { return parseMethod(n); }
};
template <>
struct Named<DebugView> {
  static std::vector<DebugView> all() { return allDebugViews(); }
  static const char* name(DebugView v) { return debugViewName(v); }
  static std::optional<DebugView> parse(std::string_view n) { return parseDebugView(n); }
};
template <class T, const auto& kTable>
struct NamedByTable {
  static std::vector<T> all() { return valuesOf(kTable); }
  static const char* name(T v) { return nameOf(kTable, v); }
  static std::optional<T> parse(std::string_view n) { return valueOf(kTable, n); }
};
template <>
struct Named<hsdf::NormalMode> : NamedByTable<hsdf::NormalMode, kNormalModes> {};
template <>
struct Named<SplitMode> : NamedByTable<SplitMode, kSplitModes> {};
template <>
struct Named<AutoSwitch> : NamedByTable<AutoSwitch, kAutoSwitches> {};
template <>
struct Named<hsdf::NodeDraw> : NamedByTable<hsdf::NodeDraw, kNodeDraws> {};

template <class T>
concept IsNamed = requires(T v) { Named<T>::name(v); };
template <class T>
concept IsNumber = std::is_arithmetic_v<T> && !std::is_same_v<T, bool>;
using Names = std::vector<std::string>;

// The value type of a member pointer.
template <class M>
using ValueOf = std::remove_cvref_t<decltype(std::declval<TuningState&>().*std::declval<M>())>;

template <class T>
bool allowed(const TuningField& field, T value) {
  if constexpr (std::is_same_v<T, Method>) return !field.sdfMethodsOnly || isSdfMethod(value);
  return true;
}

template <class T>
std::vector<T> allowedValues(const TuningField& field) {
  std::vector<T> values = Named<T>::all();
  std::erase_if(values, [&field](T v) { return !allowed(field, v); });
  return values;
}

template <class T>
std::string joinNames(const std::vector<T>& values) {
  std::string names;
  for (const T v : values) names += (names.empty() ? "" : ", ") + std::string(Named<T>::name(v));
  return names;
}

// ---- Reading a settings file's value (and a --script value, read as JSON) ----

engine::Status outside(double value, const TuningField& f, bool asFloat) {
  if (asFloat)
    return engine::makeError(fmt::format("{} is outside {}..{}", value, float(f.range.min), float(f.range.max)));
  return engine::makeError(fmt::format("{} is outside {}..{}", value, static_cast<long long>(f.range.min), static_cast<long long>(f.range.max)));
}

template <IsNumber T>
  requires std::is_integral_v<T>
engine::Status read(const json& value, const TuningField& f, T& out) {
  if (!value.is_number_integer()) return engine::makeError(fmt::format("expected an integer, got {}", value.dump()));
  const long long v = value.get<long long>();
  const bool derived = f.zeroIsDerived && v == 0;
  if (!derived && (v < static_cast<long long>(f.range.min) || v > static_cast<long long>(f.range.max))) return outside(double(v), f, false);
  out = T(v);  // a value of `choices`: validateTuning, whose message names them
  return {};
}

template <IsNumber T>
  requires std::is_floating_point_v<T>
engine::Status read(const json& value, const TuningField& f, T& out) {
  if (!value.is_number()) return engine::makeError(fmt::format("expected a number, got {}", value.dump()));
  // Compared as the float it is stored as: the bounds are floats, and 0.05 written in a file is a
  // hair below 0.05f as a double, so a bound the message names would be refused.
  const double v = value.get<double>();
  const float f32 = float(v);
  if (!(f32 >= float(f.range.min) && f32 <= float(f.range.max))) return outside(v, f, true);
  out = f32;
  return {};
}

engine::Status read(const json& value, const TuningField&, bool& out) {
  if (!value.is_boolean()) return engine::makeError(fmt::format("expected true or false, got {}", value.dump()));
  out = value.get<bool>();
  return {};
}

// true (on), false (off) or "auto": a switch written as the bool it is when the user decided.
engine::Status read(const json& value, const TuningField&, AutoSwitch& out) {
  if (value.is_boolean()) {
    out = value.get<bool>() ? AutoSwitch::On : AutoSwitch::Off;
    return {};
  }
  if (value.is_string() && value.get<std::string>() == "auto") {
    out = AutoSwitch::Auto;
    return {};
  }
  return engine::makeError(fmt::format("expected true, false or \"auto\", got {}", value.dump()));
}

template <IsNamed T>
engine::Status read(const json& value, const TuningField& f, T& out) {
  const std::optional<T> parsed = value.is_string() ? Named<T>::parse(value.get<std::string>()) : std::nullopt;
  if (!parsed) return engine::makeError(fmt::format("{} is not one of {}", value.dump(), joinNames(Named<T>::all())));
  // A name of the kind that this field does not take (mesh as the compared method): said so.
  if (!allowed(f, *parsed))
    return engine::makeError(fmt::format("the {} must be an SDF method ({})", f.label, joinNames(allowedValues<T>(f))));
  out = *parsed;
  return {};
}

// An array of names, or (a --script line) one string of names separated by commas. An empty name is
// refused: it would match only unnamed nodes.
engine::Status read(const json& value, const TuningField&, Names& out) {
  Names names;
  if (value.is_string()) {
    const std::string text = value.get<std::string>();
    for (std::size_t start = 0, end = 0; end != std::string::npos && !text.empty(); start = end + 1) {
      end = text.find(',', start);
      names.push_back(text.substr(start, end == std::string::npos ? end : end - start));
    }
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

engine::Status readField(const TuningField& f, const json& value, TuningState& t) {
  return std::visit([&](auto member) { return read(value, f, t.*member); }, f.member);
}

engine::Status readKey(const std::string& key, const json& value, TuningState& t) {
  const TuningField* field = findTuningField(key);
  if (!field) return engine::makeError("unknown setting (known: " + tuningKeyList() + ")");
  return readField(*field, value, t);
}

// ---- Writing ----

template <class T>
json toJson(const T& value) {
  if constexpr (std::is_same_v<T, AutoSwitch>) return value == AutoSwitch::Auto ? json("auto") : json(value == AutoSwitch::On);
  else if constexpr (IsNamed<T>) return json(Named<T>::name(value));
  else return json(value);
}

template <class T>
std::string toText(const T& value) {
  if constexpr (std::is_same_v<T, bool>) return value ? "true" : "false";
  else if constexpr (IsNamed<T>) return Named<T>::name(value);
  else if constexpr (std::is_same_v<T, Names>) return fmt::format("{}", fmt::join(value, ","));
  else return fmt::format("{}", value);
}

// ---- The table ----

NumberRange numbers(IntRange r) { return {double(r.min), double(r.max)}; }
NumberRange numbers(FloatRange r) { return {double(r.min), double(r.max)}; }

// The rows, in the order of --help and of a settings file's keys. Help says what a setting does and
// why one would change it; the range, the names and the default come from the row (tuningHelp).
std::vector<TuningField> makeFields() {
  using S = TuningState;
  using Cells = hsdf::HermiteCellFeature;
  return {
      {.key = "method", .option = "--method", .label = "method",
       .help = "mesh (the scene's triangles), cells (Hermite cells, the paper's method; cells-runs, cell-bricks: "
               "fewer, larger proxies), trilinear or hermite (sphere tracing)",
       .member = &S::method},
      {.key = "resolution", .option = "--resolution", .label = "K (resolution)",
       .help = fmt::format("samples per axis K of the baked field (changing it re-bakes); trilinear and hermite up "
                           "to {}, cells past {} bake sparse",
                           kDenseResolutionRange.max, kDenseBakeMaxResolution),
       .member = &S::resolution, .range = numbers(kResolutionRange)},
      {.key = "padding", .option = "--padding", .label = "padding",
       .help = "cells of padding around the mesh bounds (changing it re-bakes)", .member = &S::padding,
       .range = numbers(kPaddingRange)},
      {.key = "shell", .option = "--shell", .label = "shell thickness",
       .help = "above 0: the meshes baked as shells this thick (scene units) around their triangles, for sheets "
               "and open surfaces that bound no volume; 0 bakes the solids they bound (changing it re-bakes; with "
               "--objects, a node's extras hermite_sdf.shell wins for its mesh)",
       .member = &S::shellThickness, .range = numbers(kShellThicknessRange)},
      {.key = "subdivisions", .option = "--subdivisions", .label = "n (subdivisions)",
       .help = "n, equidistant evaluations per cell segment (the paper: 2 or 3)", .member = &S::subdivisions,
       .range = numbers(kSubdivisionsRange)},
      {.key = "refine", .option = "--refine", .label = "refinement",
       .help = "root refinement steps after the linear interpolation", .member = &S::refineSteps,
       .range = numbers(kRefineRange)},
      {.key = "normals", .option = "--normals", .label = "exact normals (off: central diff.)",
       .help = "normals: exact (the interpolant's gradient) or central (differences)", .member = &S::normals},
      {.key = "fp16", .option = "--fp16", .label = "fp16", .help = "half-precision cell records / textures",
       .member = &S::fp16, .boolOption = BoolOption::Flag},
      {.key = "debug_view", .option = "--debug-view", .label = "debug view",
       .help = "what the frame shows: none (shaded), normals, depth, cells, evals (evaluations per pixel) or "
               "wireframe (cell boxes)",
       .member = &S::debugView},
      {.key = "front_to_back", .option = "--no-front-to-back", .label = "front to back",
       .help = "cells: submit rows of cells front to back (off: in storage order)", .member = &S::frontToBack,
       .boolOption = BoolOption::NegatedFlag},
      {.key = "early_depth", .option = "--early-depth", .label = "early depth",
       .help = "cells: the early depth stage, boxes tested at their faces' depth so that boxes behind a found hit "
               "skip the search; auto: on for software rasterizers (lavapipe), off on GPUs, where it costs more "
               "than it saves",
       .member = &S::earlyDepth},
      {.key = "certified", .option = "--certified", .label = "certified roots",
       .help = "cells: certified root search (Bernstein subdivision of the ray's cubic; never misses the first "
               "root) instead of n samples",
       .member = &S::certified, .boolOption = BoolOption::Flag},
      {.key = "cull_bricks", .option = "--cull-bricks", .label = "cull bricks",
       .help = "cell bricks: a compute pass keeps only the bricks in the frustum whose normal cone may face the eye",
       .member = &S::cullBricks},
      {.key = "cull_cells", .option = "--cull-cells", .label = "cull cells",
       .help = "cells: a compute pass keeps only the cells in the frustum whose normal cone may face the eye",
       .member = &S::cullCells},
      {.key = "cull_occlusion", .option = "--cull-occlusion", .label = "cull occlusion",
       .help = "cells (with cull cells): two-phase occlusion culling, last frame's visible cells drawn first and "
               "the rest tested against the depth pyramid of what they drew",
       .member = &S::cullOcclusion},
      {.key = "proxy_boxes", .option = "--proxy-boxes", .label = "proxy boxes",
       .help = "cells, runs, bricks: each cell drawn and searched over the part of it that can hold its surface "
               "(the same roots, fewer fragments and searches); off: the whole cell, as the paper",
       .member = &S::proxyBoxes},
      {.key = "thin_boxes", .option = "--thin-boxes", .label = "thin boxes",
       .help = fmt::format("cells: 12 bytes of varyings per box, the cell's record read by address in the fragment "
                           "shader; auto: on GPUs when cells cover at most {:g} pixels",
                           Cells::kThinBoxesMaxCellPixels),
       .member = &S::thinBoxes},
      {.key = "tiles", .option = "--tiles", .label = "tiles",
       .help = "cells (with cull cells): the kept cells binned into screen tiles (tile size), each drawn as a point "
               "where the device can, else a quad, whose fragments search the tile's cells, instead of a box per "
               "cell; auto: on for software rasterizers",
       .member = &S::tiles},
      {.key = "tile_size", .option = "--tile-size", .label = "tile size",
       .help = "tiles: their side in pixels; smaller tiles list fewer cells a pixel cannot see, but there are more "
               "of them to bin, sort and draw",
       .member = &S::tileSize, .range = {double(kTileSizes[0]), double(std::end(kTileSizes)[-1])},
       .choices = kTileSizes},
      {.key = "split", .option = "--split", .label = "split",
       .help = "split-screen comparison: off, or a vertical or horizontal divider (the compared method right of "
               "or below it)",
       .member = &S::split},
      {.key = "split_position", .option = "--split-position", .label = "divider",
       .help = "the divider, as a fraction of the width (vertical) or height", .member = &S::splitPosition,
       .range = numbers(kSplitPositionRange)},
      {.key = "compare_method", .option = "--compare-method", .label = "compared method",
       .help = "the compared side's SDF method", .member = &S::compareMethod, .sdfMethodsOnly = true},
      {.key = "compare_resolution", .option = "--compare-resolution", .label = "compared K (0: 2K)",
       .help = fmt::format("K of the compared side, within its method's range (trilinear, hermite up to {}); 0: "
                           "twice K, at most {}",
                           kDenseResolutionRange.max, kDefaultCompareResolutionMax),
       .member = &S::compareResolution, .range = numbers(kResolutionRange), .zeroIsDerived = true},
      {.key = "compare_normals", .option = "--compare-normals",
       .label = "compared side: exact normals (off: central diff.)",
       .help = "normals of the compared side: exact or central (the paper's for trilinear)",
       .member = &S::compareNormals},
      {.key = "difference", .option = "--difference", .label = "difference view (normal angle)",
       .help = "difference view: the angle between the two methods' normals as a heat map, and the pixels one "
               "method covers and the other does not",
       .member = &S::difference, .boolOption = BoolOption::Flag},
      {.key = "node_draw", .option = "--node-draw", .label = "node draw",
       .help = "--objects: how nodes without an extras choice draw", .member = &S::nodeDraw},
      {.key = "triangle_nodes", .option = "--triangle-nodes", .label = "triangle nodes",
       .help = "--objects: names of nodes drawn as triangles (comma-separated)", .member = &S::triangleNodes},
      {.key = "lod", .option = "--lod", .label = "levels of detail",
       .help = "levels of detail: bake K/2, K/4, ... too and draw each frame the coarsest level whose cells fit "
               "the target size",
       .member = &S::lod, .boolOption = BoolOption::Flag},
      {.key = "lod_pixels_per_cell", .option = "--lod-pixels-per-cell", .label = "px per cell",
       .help = "levels of detail: the target size of a drawn cell in pixels", .member = &S::lodPixelsPerCell,
       .range = numbers(kLodPixelsPerCellRange)},
      {.key = "trace_epsilon", .option = "--trace-epsilon", .label = "log10 epsilon (h)",
       .help = "sphere tracers: stop when |f| is below this many grid spacings", .member = &S::traceEpsilon,
       .range = numbers(kTraceEpsilonRange)},
      {.key = "trace_max_steps", .option = "--trace-max-steps", .label = "max steps",
       .help = "sphere tracers: field evaluations per ray before giving up (counted as out of steps)",
       .member = &S::traceMaxSteps, .range = numbers(kTraceMaxStepsRange)},
      {.key = "central_difference_step", .option = "--central-difference-step", .label = "central difference step (h)",
       .help = "central-difference normals: the step in grid spacings", .member = &S::centralDifferenceStep,
       .range = numbers(kCentralDifferenceStepRange)},
      {.key = "max_run_length", .option = "--max-run-length", .label = "max run length",
       .help = "cells-runs: the most cells one run's box covers", .member = &S::maxRunLength,
       .range = numbers(kMaxRunLengthRange)},
      {.key = "upload_mib_per_frame", .option = "--upload-mib-per-frame", .label = "upload MiB/frame (0: no limit)",
       .help = "cells, runs, bricks: the MiB of cell records one frame uploads when a new asset comes; a larger "
               "asset is uploaded over several frames and drawn once all of it is in (meanwhile the object draws "
               "what it drew before); 0: no limit. Headless runs (screenshots, perf captures) upload without one",
       .member = &S::uploadMiBPerFrame, .range = numbers(kUploadMiBPerFrameRange)},
  };
}

bool isFloatField(const TuningField& field) { return std::holds_alternative<float TuningState::*>(field.member); }

// "2..2048", "0.05..0.95": the range as the messages name it (a float's bounds as the floats checked).
std::string numberRange(const TuningField& f) {
  if (isFloatField(f)) return fmt::format("{}..{}", float(f.range.min), float(f.range.max));
  return fmt::format("{}..{}", static_cast<long long>(f.range.min), static_cast<long long>(f.range.max));
}

// What --help says a number takes: the range, the choices ("4, 8 or 16"), 0 when it stands for a
// derived value.
std::string rangeText(const TuningField& f) {
  if (!f.choices.empty()) {
    const std::string most = fmt::format("{}", fmt::join(f.choices.first(f.choices.size() - 1), ", "));
    return fmt::format("{} or {}", most, f.choices.back());
  }
  return f.zeroIsDerived ? "0 or " + numberRange(f) : numberRange(f);
}

}  // namespace

const char* normalModeName(hsdf::NormalMode mode) { return nameOf(kNormalModes, mode); }
std::optional<hsdf::NormalMode> parseNormalMode(std::string_view name) { return valueOf(kNormalModes, name); }
const char* autoSwitchName(AutoSwitch mode) { return nameOf(kAutoSwitches, mode); }
std::optional<AutoSwitch> parseAutoSwitch(std::string_view name) { return valueOf(kAutoSwitches, name); }
const char* splitModeName(SplitMode mode) { return nameOf(kSplitModes, mode); }
std::optional<SplitMode> parseSplitMode(std::string_view name) { return valueOf(kSplitModes, name); }

std::span<const TuningField> tuningFields() {
  static const std::vector<TuningField> fields = makeFields();
  return fields;
}

const TuningField* findTuningField(std::string_view key) {
  for (const TuningField& field : tuningFields())
    if (key == field.key) return &field;
  return nullptr;
}

const TuningField& tuningField(std::string_view key) {
  if (const TuningField* field = findTuningField(key)) return *field;
  std::fprintf(stderr, "tuningField: '%.*s' is not a key of the tuning table\n", int(key.size()), key.data());
  std::abort();
}

bool isTuningKey(std::string_view key) { return findTuningField(key) != nullptr; }

std::string tuningKeyList() {
  std::string list;
  for (const TuningField& field : tuningFields()) list += (list.empty() ? "" : ", ") + std::string(field.key);
  return list;
}

TuningKind tuningKind(const TuningField& field) {
  return std::visit(
      [](auto member) {
        using T = ValueOf<decltype(member)>;
        if constexpr (std::is_same_v<T, bool>) return TuningKind::Bool;
        else if constexpr (IsNumber<T>) return TuningKind::Number;
        else if constexpr (IsNamed<T>) return TuningKind::Name;
        else return TuningKind::Names;
      },
      field.member);
}

std::vector<std::string> tuningNames(const TuningField& field) {
  return std::visit(
      [&field](auto member) {
        std::vector<std::string> names;
        using T = ValueOf<decltype(member)>;
        if constexpr (IsNamed<T>)
          for (const T v : allowedValues<T>(field)) names.emplace_back(Named<T>::name(v));
        return names;
      },
      field.member);
}

std::string tuningValueText(const TuningField& field, const TuningState& tuning) {
  return std::visit([&tuning](auto member) { return toText(tuning.*member); }, field.member);
}

std::string tuningHelp(const TuningField& field) {
  const std::string fallback = tuningValueText(field, TuningState{});
  switch (tuningKind(field)) {
    case TuningKind::Number:
      return fmt::format("{} ({}, default {})", field.help, rangeText(field), fallback);
    case TuningKind::Bool:
      if (field.boolOption == BoolOption::Flag) return field.help + " (off by default)";
      if (field.boolOption == BoolOption::NegatedFlag) return field.help + " (on by default; this option turns it off)";
      return fmt::format("{} (true or false, default {})", field.help, fallback);
    case TuningKind::Name: return fmt::format("{} (default {})", field.help, fallback);
    case TuningKind::Names: break;
  }
  return field.help;
}

engine::Status setTuningFromText(const TuningField& field, std::string_view text, TuningState& tuning) {
  return std::visit(
      [&](auto member) -> engine::Status {
        using T = ValueOf<decltype(member)>;
        if constexpr (IsNamed<T>) {  // the command line's names (an auto switch: auto, on, off)
          const std::optional<T> value = Named<T>::parse(text);
          if (!value || !allowed(field, *value))
            return engine::makeError(fmt::format("'{}' is not one of {}", text, joinNames(allowedValues<T>(field))));
          tuning.*member = *value;
          return {};
        } else {
          json parsed = json::parse(text, nullptr, /*allow_exceptions=*/false);
          if (parsed.is_discarded() || !(parsed.is_number() || parsed.is_boolean())) parsed = std::string(text);
          return read(parsed, field, tuning.*member);
        }
      },
      field.member);
}

bool sameTuningValue(const TuningField& field, const TuningState& a, const TuningState& b) {
  return std::visit([&](auto member) { return a.*member == b.*member; }, field.member);
}

engine::Status checkTuningRange(const TuningField& field, const TuningState& tuning) {
  return std::visit(
      [&](auto member) -> engine::Status {
        using T = ValueOf<decltype(member)>;
        if constexpr (IsNumber<T>) {
          const T value = tuning.*member;
          if (field.zeroIsDerived && value == T(0)) return {};
          // A float against the float bounds it was read with (see read); false for NaN.
          const bool inside = std::is_floating_point_v<T>
                                  ? (float(value) >= float(field.range.min) && float(value) <= float(field.range.max))
                                  : (double(value) >= field.range.min && double(value) <= field.range.max);
          if (!inside) return engine::makeError(fmt::format("{} {} is outside {}", field.option, value, numberRange(field)));
          const bool chosen = field.choices.empty() ||
                              std::find(field.choices.begin(), field.choices.end(), std::uint32_t(value)) != field.choices.end();
          if (!chosen)
            return engine::makeError(fmt::format("{} {} is not one of {}", field.option, value, fmt::join(field.choices, ", ")));
        }
        return {};
      },
      field.member);
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
  json root = json::object();
  for (const TuningField& field : tuningFields())
    root[field.key] = std::visit([&t](auto member) { return toJson(t.*member); }, field.member);
  return engine::writeTextFile(file, root.dump(2) + "\n");
}

}  // namespace samples
