#include "tuning.h"

#include <array>
#include <utility>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "engine/core/files.h"
#include "shared/host_device.h"

namespace samples {
namespace {

template <class T, std::size_t N>
using NameTable = std::array<std::pair<T, const char*>, N>;

constexpr NameTable<Method, 4> kMethods{{{Method::Mesh, "mesh"},
                                         {Method::Cells, "cells"},
                                         {Method::Trilinear, "trilinear"},
                                         {Method::Hermite, "hermite"}}};
constexpr NameTable<hsdf::NormalMode, 2> kNormalModes{
    {{hsdf::NormalMode::Exact, "exact"}, {hsdf::NormalMode::CentralDifferences, "central"}}};
constexpr NameTable<DebugView, 6> kDebugViews{{{DebugView::None, "none"},
                                               {DebugView::Normals, "normals"},
                                               {DebugView::Depth, "depth"},
                                               {DebugView::Cells, "cells"},
                                               {DebugView::Evals, "evals"},
                                               {DebugView::Wireframe, "wireframe"}}};
static_assert(std::uint32_t(DebugView::Normals) == DEBUG_VIEW_NORMALS && std::uint32_t(DebugView::Depth) == DEBUG_VIEW_DEPTH &&
              std::uint32_t(DebugView::Cells) == DEBUG_VIEW_CELLS && std::uint32_t(DebugView::Evals) == DEBUG_VIEW_EVALS &&
              std::uint32_t(DebugView::Wireframe) == DEBUG_VIEW_WIREFRAME && std::uint32_t(DebugView::None) == DEBUG_VIEW_NONE);

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

engine::Status readBool(const json& value, bool& out) {
  if (!value.is_boolean()) return engine::makeError(fmt::format("expected true or false, got {}", value.dump()));
  out = value.get<bool>();
  return {};
}

template <class T, std::size_t N>
engine::Status readName(const json& value, const NameTable<T, N>& table, T& out) {
  const std::optional<T> parsed = value.is_string() ? valueOf(table, value.get<std::string>()) : std::nullopt;
  if (!parsed) return engine::makeError(fmt::format("{} is not one of {}", value.dump(), allNames(table)));
  out = *parsed;
  return {};
}

engine::Status readKey(const std::string& key, const json& value, TuningState& t) {
  int n = 0;
  if (key == "method") return readName(value, kMethods, t.method);
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
  if (key == "debug_view") return readName(value, kDebugViews, t.debugView);
  if (key == "front_to_back") return readBool(value, t.frontToBack);
  if (key == "certified") return readBool(value, t.certified);
  return engine::makeError("unknown setting (known: method, resolution, padding, subdivisions, refine, normals, fp16, "
                           "debug_view, front_to_back, certified)");
}

}  // namespace

const char* methodName(Method method) { return nameOf(kMethods, method); }
std::optional<Method> parseMethod(std::string_view name) { return valueOf(kMethods, name); }
bool isSdfMethod(Method method) { return method != Method::Mesh; }
const char* normalModeName(hsdf::NormalMode mode) { return nameOf(kNormalModes, mode); }
std::optional<hsdf::NormalMode> parseNormalMode(std::string_view name) { return valueOf(kNormalModes, name); }
const char* debugViewName(DebugView view) { return nameOf(kDebugViews, view); }
std::optional<DebugView> parseDebugView(std::string_view name) { return valueOf(kDebugViews, name); }

engine::Status validateTuning(const TuningState& t) {
  ENGINE_TRY(checkRange("--resolution", t.resolution, kResolutionRange));
  ENGINE_TRY(checkRange("--padding", t.padding, kPaddingRange));
  ENGINE_TRY(checkRange("--subdivisions", t.subdivisions, kSubdivisionsRange));
  ENGINE_TRY(checkRange("--refine", t.refineSteps, kRefineRange));
  if (t.resolution - 1 - 2 * t.padding < 1)
    return engine::makeError(
        fmt::format("--resolution {} leaves no cells inside --padding {}", t.resolution, t.padding));
  return {};
}

void applyTuning(const TuningState& tuning, hsdf::HermiteSdfRenderable& renderable) {
  if (tuning.method == Method::Cells) renderable.method = hsdf::RenderMethod::Cells;
  if (tuning.method == Method::Trilinear) renderable.method = hsdf::RenderMethod::TrilinearSphereTrace;
  if (tuning.method == Method::Hermite) renderable.method = hsdf::RenderMethod::HermiteSphereTrace;
  renderable.subdivisions = tuning.subdivisions;
  renderable.refineSteps = tuning.refineSteps;
  renderable.normals = tuning.normals;
  renderable.halfPrecision = tuning.fp16;
  renderable.certified = tuning.certified;
}

engine::Status setTuningValue(TuningState& tuning, std::string_view key, std::string_view value) {
  json parsed = json::parse(value, nullptr, /*allow_exceptions=*/false);
  if (parsed.is_discarded() || !(parsed.is_number() || parsed.is_boolean())) parsed = std::string(value);
  TuningState changed = tuning;
  ENGINE_TRY(readKey(std::string(key), parsed, changed).withContext(fmt::format("setting '{}'", key)));
  ENGINE_TRY(validateTuning(changed));
  tuning = changed;
  return {};
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
  const json root = {{"method", methodName(t.method)},
                     {"resolution", t.resolution},
                     {"padding", t.padding},
                     {"subdivisions", t.subdivisions},
                     {"refine", t.refineSteps},
                     {"normals", normalModeName(t.normals)},
                     {"fp16", t.fp16},
                     {"debug_view", debugViewName(t.debugView)},
                     {"front_to_back", t.frontToBack},
                     {"certified", t.certified}};
  return engine::writeTextFile(file, root.dump(2) + "\n");
}

}  // namespace samples
