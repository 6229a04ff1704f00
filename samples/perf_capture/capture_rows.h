#pragma once
// The rows of the capture: method x K x setting. Each setting is one line of kVariants
// (capture_rows.cpp); a new variant (e.g. a cell root-search mode, or a `cells-runs` method) is
// one more line there.
#include <cstdint>
#include <string>
#include <vector>

#include "hermite_sdf/render/renderable.h"
#include "tuning.h"

namespace capture {

struct Options;

struct RowSpec {
  std::string method;        // results.csv `method`: mesh, trilinear, hermite, cells
  std::string label;         // human-readable, unique per row: "cells n=3 r=1 fp16 K=32"
  samples::TuningState state;  // what the Viewer draws the row with (K included)
  // Read from `state` for the outputs (n and r are 0 for the tracers and the mesh):
  int resolution = 0;        // K (0 for the mesh)
  hsdf::RenderMethod render = hsdf::RenderMethod::Cells;
  std::uint32_t subdivisions = 0;
  std::uint32_t refine = 0;
  hsdf::NormalMode normals = hsdf::NormalMode::Exact;
  bool fp16 = false;
  // Which row of the Markdown table this one is compared in (the paper's columns): the trilinear
  // baseline (central differences, the paper's), dense Hermite, cells n=3 r=1 fp32.
  bool paperColumn = false;

  bool isMesh() const { return method == "mesh"; }
  // The row as the one settings struct every sample writes (samples/common/tuning.h): what the
  // Viewer is given for this row (no debug view: timed frames are shaded as a user sees them).
  samples::TuningState tuning() const;
  std::string normalsName() const;  // results.csv `normals`: exact, central (mesh: face)
};

// Every row the options ask for, grouped by K (ascending; the mesh first). Trilinear rows also
// run at 2K (up to 256) for every K asked: the paper's rule of thumb that Hermite at K looks like
// trilinear at 2K.
std::vector<RowSpec> buildRows(const Options& options);

// The settings labels of the cell methods' rows ("n=3 r=1", "certified", ...), for --settings.
std::vector<std::string> cellSettingNames();

}  // namespace capture
