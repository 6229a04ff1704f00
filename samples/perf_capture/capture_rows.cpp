#include "capture_rows.h"

#include <algorithm>
#include <set>

#include <fmt/format.h>

#include "capture_options.h"

namespace capture {
namespace {

using hsdf::NormalMode;
using hsdf::RenderMethod;

// One line per setting of an SDF method: the CSV method, the label's setting and the row's
// TuningState (everything but K). A new variant, e.g. another cell root-search mode once
// TuningState has it, is one more line; so is a new method with its samples::Method.
struct Variant {
  const char* method;
  const char* setting;
  bool paperColumn;  // compared with the paper's columns (RowSpec::paperColumn)
  samples::TuningState tuning;
};

using samples::Method;
const Variant kVariants[] = {
    {"trilinear", "central", true, {.method = hsdf::RenderMethod::TrilinearSphereTrace, .normals = NormalMode::CentralDifferences}},
    {"trilinear", "exact", false, {.method = hsdf::RenderMethod::TrilinearSphereTrace, .normals = NormalMode::Exact}},
    {"hermite", "", true, {.method = hsdf::RenderMethod::HermiteSphereTrace, .normals = NormalMode::Exact}},
    {"cells", "n=2 r=0", false, {.method = hsdf::RenderMethod::Cells, .subdivisions = 2, .refineSteps = 0}},
    {"cells", "n=2 r=1", false, {.method = hsdf::RenderMethod::Cells, .subdivisions = 2, .refineSteps = 1}},
    {"cells", "n=3 r=0", false, {.method = hsdf::RenderMethod::Cells, .subdivisions = 3, .refineSteps = 0}},
    {"cells", "n=3 r=1", true, {.method = hsdf::RenderMethod::Cells, .subdivisions = 3, .refineSteps = 1}},
    // The fp16 target compares this one with the fp32 line above.
    {"cells", "n=3 r=1 fp16", false, {.method = hsdf::RenderMethod::Cells, .subdivisions = 3, .refineSteps = 1, .fp16 = true}},
    // What the cell culling pass removes: the same cells, every box drawn.
    {"cells", "n=3 r=1 no-cull", false,
     {.method = hsdf::RenderMethod::Cells, .subdivisions = 3, .refineSteps = 1, .cullCells = false}},
    // Two-phase occlusion culling on top of the frustum and cones (off by default: see
    // HermiteCellFeature::Settings::cullOcclusion). This row and the thin / attribute rows below
    // are box variants: boxes on every device (Tiles::Auto would draw tiles on lavapipe).
    {"cells", "n=3 r=1 occlusion", false,
     {.method = hsdf::RenderMethod::Cells, .subdivisions = 3, .refineSteps = 1, .cullOcclusion = true,
      .tiles = samples::AutoSwitch::Off}},
    // Issue 20 step 2: the same cells and search with 12 bytes of varyings per box (records read by
    // address), and with the Hermite data as varyings (the paper's); the row above lets the device
    // and the cells' size on screen choose (HermiteCellFeature::ThinBoxes::Auto).
    {"cells", "n=3 r=1 thin", false,
     {.method = hsdf::RenderMethod::Cells, .subdivisions = 3, .refineSteps = 1, .thinBoxes = samples::AutoSwitch::On,
      .tiles = samples::AutoSwitch::Off}},
    {"cells", "n=3 r=1 attributes", false,
     {.method = hsdf::RenderMethod::Cells, .subdivisions = 3, .refineSteps = 1, .thinBoxes = samples::AutoSwitch::Off,
      .tiles = samples::AutoSwitch::Off}},
    // Issue 20: the culled cells as screen tiles and as boxes (the row above lets the device choose,
    // HermiteCellFeature::Tiles::Auto: tiles on software rasterizers).
    {"cells", "n=3 r=1 tiles", false,
     {.method = hsdf::RenderMethod::Cells, .subdivisions = 3, .refineSteps = 1, .tiles = samples::AutoSwitch::On}},
    // Tiles of 4x4 and 16x16 pixels (HermiteCellFeature::Settings::tileSize): smaller tiles have
    // shorter lists (fewer mask words per pixel, a lane's entries nearer its own) but make more
    // entries and tiles to bin, sort and draw; larger ones the other way round.
    {"cells", "n=3 r=1 tiles 4x4", false,
     {.method = hsdf::RenderMethod::Cells, .subdivisions = 3, .refineSteps = 1, .tiles = samples::AutoSwitch::On,
      .tileSize = 4}},
    {"cells", "n=3 r=1 tiles 16x16", false,
     {.method = hsdf::RenderMethod::Cells, .subdivisions = 3, .refineSteps = 1, .tiles = samples::AutoSwitch::On,
      .tileSize = 16}},
    {"cells", "n=3 r=1 boxes", false,
     {.method = hsdf::RenderMethod::Cells, .subdivisions = 3, .refineSteps = 1, .tiles = samples::AutoSwitch::Off}},
    // The paper's proxy, the whole cell, against the cells' proxy boxes (the rows above; cells.h,
    // "Proxy boxes"): as tiles and as boxes.
    {"cells", "n=3 r=1 tiles whole cells", false,
     {.method = hsdf::RenderMethod::Cells, .subdivisions = 3, .refineSteps = 1, .proxyBoxes = false,
      .tiles = samples::AutoSwitch::On}},
    {"cells", "n=3 r=1 boxes whole cells", false,
     {.method = hsdf::RenderMethod::Cells, .subdivisions = 3, .refineSteps = 1, .proxyBoxes = false,
      .tiles = samples::AutoSwitch::Off}},
    // The certified root search (docs/root-finding.md): its cost against the paper's fixed n above.
    {"cells", "certified", false, {.method = hsdf::RenderMethod::Cells, .subdivisions = 3, .refineSteps = 1, .certified = true}},
    // Issue 13's variant: the same cells and search, one box per run of cells along x.
    {"cells-runs", "n=3 r=1", false, {.method = hsdf::RenderMethod::CellRuns, .subdivisions = 3, .refineSteps = 1}},
    {"cells-runs", "n=3 r=1 fp16", false, {.method = hsdf::RenderMethod::CellRuns, .subdivisions = 3, .refineSteps = 1, .fp16 = true}},
    // Issue 20's variant: the same cells and search, one box per brick of 4x4x4 cells.
    {"cell-bricks", "n=3 r=1", false, {.method = hsdf::RenderMethod::CellBricks, .subdivisions = 3, .refineSteps = 1}},
    {"cell-bricks", "n=3 r=1 fp16", false, {.method = hsdf::RenderMethod::CellBricks, .subdivisions = 3, .refineSteps = 1, .fp16 = true}},
    // What the brick culling pass removes: the same bricks, every one drawn.
    {"cell-bricks", "n=3 r=1 no-cull", false,
     {.method = hsdf::RenderMethod::CellBricks, .subdivisions = 3, .refineSteps = 1, .cullBricks = false}},
};

bool wanted(const Options& options, const std::string& method) {
  return std::find(options.methods.begin(), options.methods.end(), method) != options.methods.end();
}

// --settings: the tracers' rows (no cell setting) always; cell rows only when their setting is listed.
bool wantedSetting(const Options& options, const Variant& v) {
  if (options.cellSettings.empty() || !samples::drawsCells(v.tuning.method)) return true;
  return std::find(options.cellSettings.begin(), options.cellSettings.end(), v.setting) != options.cellSettings.end();
}

// The row of variant v at K, with levels of detail on or off.
RowSpec makeRow(const Variant& v, int k, bool lod) {
  RowSpec row;
  row.method = v.method;
  row.label = std::string(v.method) + (*v.setting ? " " : "") + v.setting + (lod ? " lod" : "") + fmt::format(" K={}", k);
  row.state = v.tuning;
  row.state.resolution = k;
  row.state.lod = lod;
  row.resolution = k;
  // Every variant is of an SDF method (the mesh rows are not variants): its method is the row's,
  // whatever the module adds (a chain of ifs labelled a new method "cells").
  row.render = v.tuning.method.sdf().value();
  const bool cells = samples::drawsCells(v.tuning.method);  // the tracers have no n or r
  row.subdivisions = cells ? v.tuning.subdivisions : 0;
  row.refine = cells ? v.tuning.refineSteps : 0;
  row.normals = v.tuning.normals;
  row.fp16 = v.tuning.fp16;
  row.paperColumn = v.paperColumn && !lod;
  return row;
}

}  // namespace

std::string RowSpec::normalsName() const {
  if (isMesh()) return "face";
  return normals == NormalMode::Exact ? "exact" : "central";
}

samples::TuningState RowSpec::tuning() const { return state; }

std::vector<std::string> cellSettingNames() {
  std::vector<std::string> names;
  for (const Variant& v : kVariants)
    if (samples::drawsCells(v.tuning.method) && std::find(names.begin(), names.end(), v.setting) == names.end())
      names.push_back(v.setting);
  return names;
}

std::vector<RowSpec> buildRows(const Options& options) {
  std::vector<RowSpec> rows;
  if (wanted(options, "mesh")) {
    RowSpec mesh;
    mesh.method = "mesh";
    mesh.label = "mesh";
    mesh.state.method = Method::Mesh;
    rows.push_back(mesh);
  }
  std::set<int> all(options.resolutions.begin(), options.resolutions.end());
  for (int k : options.resolutions)
    if (2 * k <= 256) all.insert(2 * k);
  const std::set<int> asked(options.resolutions.begin(), options.resolutions.end());
  for (int k : all) {
    for (const Variant& v : kVariants) {
      if (!wanted(options, v.method) || !wantedSetting(options, v)) continue;
      // Only trilinear runs at the extra 2K resolutions; the dense tracers stop at their K range.
      if (!asked.contains(k) && v.tuning.method != hsdf::RenderMethod::TrilinearSphereTrace) continue;
      if (k > samples::resolutionRange(v.tuning.method).max) continue;
      for (bool lod : {false, true}) {
        if (lod && (!options.lod || !samples::drawsCells(v.tuning.method))) continue;
        rows.push_back(makeRow(v, k, lod));
      }
    }
  }
  return rows;
}

}  // namespace capture
