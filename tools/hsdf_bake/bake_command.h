#pragma once
// The two things hsdf_bake does: bake an input into an .hsdf file, and inspect (fully validate
// and summarise) an existing file. Both print to stdout, report errors on stderr and return the
// process exit code.
#include <filesystem>
#include <string>

namespace hsdf::tools {

enum class Payload { Both, Dense, Cells };

struct BakeRequest {
  std::string input;               // glTF/GLB path or analytic shape name
  std::filesystem::path output;
  int resolution = 0;              // K
  int padding = 1;                 // P cells around the bounding box
  bool fp16 = false;
  Payload payload = Payload::Both;
  int refineDepth = 0;             // de Casteljau refinement of ambiguous cells
  bool falsePositives = false;     // count kept cells that dense sampling finds empty
  unsigned threads = 0;            // 0: all hardware threads
  double shell = 0.0;              // > 0: a shell this thick around the triangles (BakeSettings::shellThickness)
  bool progress = true;
};

int runBake(const BakeRequest& request);
int runInspect(const std::filesystem::path& file);

}  // namespace hsdf::tools
