#include "capture_rows.h"

#include <algorithm>
#include <set>

#include <fmt/format.h>

#include "capture_options.h"

namespace capture {
namespace {

using hsdf::NormalMode;
using hsdf::RenderMethod;

// One line per setting of an SDF method.
struct Variant {
  const char* method;
  RenderMethod render;
  std::uint32_t subdivisions;
  std::uint32_t refine;
  NormalMode normals;
  bool fp16;
  bool paperColumn;
};

constexpr Variant kVariants[] = {
    {"trilinear", RenderMethod::TrilinearSphereTrace, 0, 0, NormalMode::CentralDifferences, false, true},
    {"trilinear", RenderMethod::TrilinearSphereTrace, 0, 0, NormalMode::Exact, false, false},
    {"hermite", RenderMethod::HermiteSphereTrace, 0, 0, NormalMode::Exact, false, true},
    {"cells", RenderMethod::Cells, 2, 0, NormalMode::Exact, false, false},
    {"cells", RenderMethod::Cells, 2, 1, NormalMode::Exact, false, false},
    {"cells", RenderMethod::Cells, 3, 0, NormalMode::Exact, false, false},
    {"cells", RenderMethod::Cells, 3, 1, NormalMode::Exact, false, true},
    {"cells", RenderMethod::Cells, 3, 1, NormalMode::Exact, true, false},  // the fp16 target
};

std::string labelOf(const RowSpec& row) {
  if (row.isMesh()) return "mesh";
  std::string label = row.method;
  if (row.method == "cells") label += fmt::format(" n={} r={}", row.subdivisions, row.refine);
  if (row.method == "trilinear") label += row.normals == NormalMode::Exact ? " exact" : " central";
  if (row.fp16) label += " fp16";
  return label + fmt::format(" K={}", row.resolution);
}

bool wanted(const Options& options, const std::string& method) {
  return std::find(options.methods.begin(), options.methods.end(), method) != options.methods.end();
}

}  // namespace

std::string RowSpec::normalsName() const {
  if (isMesh()) return "face";
  return normals == NormalMode::Exact ? "exact" : "central";
}

samples::TuningState RowSpec::tuning() const {
  samples::TuningState t;
  t.method = isMesh()                                    ? samples::Method::Mesh
             : render == RenderMethod::TrilinearSphereTrace ? samples::Method::Trilinear
             : render == RenderMethod::HermiteSphereTrace   ? samples::Method::Hermite
                                                            : samples::Method::Cells;
  if (!isMesh()) t.resolution = resolution;
  if (subdivisions > 0) t.subdivisions = subdivisions;  // the tracers ignore it
  t.refineSteps = refine;
  t.normals = normals;
  t.fp16 = fp16;
  return t;
}

std::vector<RowSpec> buildRows(const Options& options) {
  std::vector<RowSpec> rows;
  if (wanted(options, "mesh")) {
    RowSpec mesh;
    mesh.method = "mesh";
    mesh.label = "mesh";
    rows.push_back(mesh);
  }
  std::set<int> all(options.resolutions.begin(), options.resolutions.end());
  for (int k : options.resolutions)
    if (2 * k <= 256) all.insert(2 * k);
  const std::set<int> asked(options.resolutions.begin(), options.resolutions.end());
  for (int k : all) {
    for (const Variant& v : kVariants) {
      if (!wanted(options, v.method)) continue;
      // Only trilinear runs at the extra 2K resolutions.
      if (!asked.contains(k) && v.render != RenderMethod::TrilinearSphereTrace) continue;
      RowSpec row;
      row.method = v.method;
      row.resolution = k;
      row.render = v.render;
      row.subdivisions = v.subdivisions;
      row.refine = v.refine;
      row.normals = v.normals;
      row.fp16 = v.fp16;
      row.paperColumn = v.paperColumn;
      row.label = labelOf(row);
      rows.push_back(row);
    }
  }
  return rows;
}

}  // namespace capture
