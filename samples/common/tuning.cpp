#include "tuning.h"

#include <algorithm>

#include <fmt/format.h>

#include "shared/host_device.h"
#include "tuning_fields.h"

// Methods and debug views by name, the rules between settings, and what a TuningState sets in the
// module. Reading, writing and the other names: the table (tuning_fields.cpp).
namespace samples {
namespace {

constexpr const char* kMeshName = "mesh";  // the one name not the module's

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

int effectiveCompareResolution(const TuningState& t) {
  return t.compareResolution > 0 ? t.compareResolution : std::min(2 * t.resolution, kDefaultCompareResolutionMax);
}

bool comparing(const TuningState& t) { return t.split != SplitMode::Off || t.difference; }

BakeKey bakeKey(const TuningState& t) { return {t.resolution, t.padding, t.shellThickness}; }
BakeKey bakeKey(const hsdf::BakeSettings& s) { return {s.resolution, s.padding, float(s.shellThickness)}; }
void setBakeKey(const BakeKey& key, hsdf::BakeSettings& s) {
  s.resolution = key.resolution;
  s.padding = key.padding;
  s.shellThickness = key.shellThickness;
}
void setBakeKey(const BakeKey& key, TuningState& t) {
  t.resolution = key.resolution;
  t.padding = key.padding;
  t.shellThickness = key.shellThickness;
}

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

// The rules that depend on more than one setting (each number's own range: the table's).
engine::Status checkMethodRanges(const TuningState& t) {
  ENGINE_TRY(checkResolution(t.method, t.resolution));
  const IntRange compared = resolutionRange(t.compareMethod);
  if (t.compareResolution != 0 && (t.compareResolution < compared.min || t.compareResolution > compared.max))
    return engine::makeError(fmt::format("--compare-resolution {} is outside {}..{}", t.compareResolution,
                                         compared.min, compared.max));
  if (!isSdfMethod(t.compareMethod))
    return engine::makeError("--compare-method mesh: the compared method must be cells, trilinear or hermite");
  return {};
}

}  // namespace

engine::Status validateTuning(const TuningState& t) {
  ENGINE_TRY(checkMethodRanges(t));
  for (const TuningField& field : tuningFields()) ENGINE_TRY(checkTuningRange(field, t));
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

void applyCapturedFrames(hsdf::HermiteCellFeature::Settings& cells, hsdf::SphereTraceFeature::Settings& tracers) {
  cells.uploadBytesPerFrame = 0;
  cells.warmPipelines = false;
  tracers.warmPipelines = false;
}

void applyTuning(const TuningState& tuning, hsdf::HermiteCellFeature::Settings& cells,
                 hsdf::SphereTraceFeature::Settings& tracers) {
  cells.frontToBack = tuning.frontToBack;
  cells.maxRunLength = tuning.maxRunLength;
  cells.uploadBytesPerFrame = std::uint64_t(tuning.uploadMiBPerFrame) << 20;
  cells.cullBricks = tuning.cullBricks;
  cells.cullCells = tuning.cullCells;
  cells.cullOcclusion = tuning.cullOcclusion;
  cells.proxyBoxes = tuning.proxyBoxes;
  cells.thinBoxes = tuning.thinBoxes;
  cells.tiles = tuning.tiles;
  cells.tileSize = tuning.tileSize;
  cells.earlyDepth = tuning.earlyDepth;
  tracers.epsilon = tuning.traceEpsilon;
  tracers.maxSteps = tuning.traceMaxSteps;
  tracers.centralDifferenceStep = tuning.centralDifferenceStep;
}

}  // namespace samples
