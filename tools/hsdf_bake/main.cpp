// hsdf_bake INPUT -o OUTPUT.hsdf --resolution K [--padding P] [--fp16] [--dense|--cells]
// hsdf_bake --inspect FILE.hsdf
#include <cstdio>
#include <exception>
#include <new>

#include <CLI/CLI.hpp>

#include "bake_command.h"
#include "hermite_sdf/core/field.h"

int main(int argc, char** argv) {
  CLI::App app{"Bakes a glTF/GLB mesh or an analytic shape into a Hermite SDF file (.hsdf)"};
  hsdf::tools::BakeRequest request;
  std::string inspect;
  bool denseOnly = false, cellsOnly = false, quiet = false;
  auto* input = app.add_option("input", request.input, "glTF/GLB file, or an analytic shape: sphere, box, torus, capsule, blob");
  auto* output = app.add_option("-o,--output", request.output, "output .hsdf file");
  auto* resolution = app.add_option("-r,--resolution", request.resolution, "K, samples per axis (2..4096)")
                         ->check(CLI::Range(2, hsdf::kMaxResolution));
  app.add_option("-p,--padding", request.padding, "cells of padding around the bounding box")->capture_default_str();
  app.add_flag("--fp16", request.fp16, "store scalars as IEEE binary16 (half the size)");
  auto* dense = app.add_flag("--dense", denseOnly, "store only the dense Hermite field");
  app.add_flag("--cells", cellsOnly, "store only the sparse cell stream (sparse bake: no dense field, cost grows with the kept cells)")->excludes(dense);
  // Checked here too (the classifier refuses it after the bake, which may take minutes).
  app.add_option("--refine", request.refineDepth, "de Casteljau refinement depth for ambiguous cells (0..2)")
      ->capture_default_str()
      ->check(CLI::Range(0, 2));
  app.add_option("--shell", request.shell,
                 "bake the triangles as a shell this thick (mesh units) instead of the solid they bound: for "
                 "surfaces without an inside (a zero-thickness wall, cloth, an open cup, a sheet)")
      ->check(CLI::PositiveNumber);
  app.add_flag("--false-positives", request.falsePositives,
               "count kept cells that dense sampling (17^3 points) finds empty");
  app.add_option("-j,--threads", request.threads, "worker threads (0: all, at most 256)")
      ->capture_default_str()
      ->check(CLI::Range(0u, 256u));
  app.add_flag("-q,--quiet", quiet, "no progress bar");
  // Given with a bake's INPUT, -o or -r it skipped the bake silently.
  app.add_option("--inspect", inspect, "validate and summarise an .hsdf file instead of baking")
      ->excludes(input)
      ->excludes(output)
      ->excludes(resolution);
  CLI11_PARSE(app, argc, argv);

  if (!inspect.empty()) return hsdf::tools::runInspect(inspect);
  if (request.input.empty() || request.output.empty() || request.resolution == 0) {
    std::fprintf(stderr, "hsdf_bake: INPUT, -o OUTPUT and --resolution K are required (see --help)\n");
    return 2;
  }
  request.payload = denseOnly ? hsdf::tools::Payload::Dense
                              : (cellsOnly ? hsdf::tools::Payload::Cells : hsdf::tools::Payload::Both);
  request.progress = !quiet;
  // The bake's own allocations are checked against the budget and reported; anything else that runs
  // out of memory (the file is assembled in memory before it is written) ends here, with a reason,
  // instead of std::terminate (exit 134, the printed summary lost).
  try {
    return hsdf::tools::runBake(request);
  } catch (const std::bad_alloc&) {
    std::fflush(stdout);
    std::fprintf(stderr, "hsdf_bake: error: out of memory (the bake at K = %d and its file do not fit in this "
                         "process's memory; a smaller --resolution, --cells or --fp16 needs less)\n",
                 request.resolution);
    return 1;
  } catch (const std::exception& e) {
    std::fflush(stdout);
    std::fprintf(stderr, "hsdf_bake: fatal: %s\n", e.what());
    return 1;
  }
}
