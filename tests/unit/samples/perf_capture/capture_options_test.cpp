// The capture's command line and rows: presets, overrides, refusals that name the option, and the
// rows each method x K x setting gives.
#include <set>

#include <gtest/gtest.h>

#include "capture_options.h"
#include "capture_rows.h"

namespace capture {
namespace {

ParseResult parse(std::vector<const char*> args) {
  args.insert(args.begin(), "perf_capture");
  return parseOptions(int(args.size()), args.data());
}

TEST(CaptureOptions, DefaultsAreTheIssuesFullRun) {
  const ParseResult r = parse({"--out", "x"});
  ASSERT_TRUE(r.options) << r.message;
  EXPECT_EQ(r.options->width, 1920u);
  EXPECT_EQ(r.options->height, 1080u);
  EXPECT_EQ(r.options->resolutions, (std::vector<int>{16, 32, 64, 128}));
  EXPECT_EQ(r.options->views, 8u);
  EXPECT_EQ(r.options->scene.filename(), "bunny.glb");
  EXPECT_FALSE(r.options->objects);
  const ParseResult objects = parse({"--out", "x", "--scene", HSDF_ASSET_DIR "/grid_scene.glb", "--objects"});
  ASSERT_TRUE(objects.options) << objects.message;
  EXPECT_TRUE(objects.options->objects);
  EXPECT_TRUE(r.options->sceneCameras.empty()) << "the orbit views by default";
  // Names and indices as given; they are looked up in the scene when it is loaded.
  const ParseResult cameras = parse({"--out", "x", "--scene", HSDF_ASSET_DIR "/grid_scene.glb", "--scene-cameras", "front,2"});
  ASSERT_TRUE(cameras.options) << cameras.message;
  EXPECT_EQ(cameras.options->sceneCameras, (std::vector<std::string>{"front", "2"}));
}

// Tricky: --quick is a preset, and options given beside it win, whatever their order.
TEST(CaptureOptions, QuickIsAPresetThatExplicitOptionsOverride) {
  const ParseResult r = parse({"--views", "3", "--out", "x", "--quick", "--size", "64x32"});
  ASSERT_TRUE(r.options) << r.message;
  EXPECT_EQ(r.options->views, 3u);
  EXPECT_EQ(r.options->width, 64u);
  EXPECT_EQ(r.options->height, 32u);
  EXPECT_EQ(r.options->resolutions, (std::vector<int>{16, 32}));
  EXPECT_EQ(r.options->frames, 2u);
}

TEST(CaptureOptions, BadValuesAreRefusedNamingTheOption) {
  struct Case {
    std::vector<const char*> args;
    const char* message;
  };
  const Case cases[] = {
      {{"--out", "x", "--resolutions", "16,,32"}, "--resolutions: '' is not a resolution"},
      // Given but empty: refused, not the default list run in its place.
      {{"--out", "x", "--resolutions", ""}, "--resolutions: an empty list"},
      {{"--out", "x", "--methods", ""}, "--methods: an empty list"},
      {{"--out", "x", "--resolutions", "4096"}, "--resolutions: '4096' is not a resolution K in 4..2048"},
      {{"--out", "x", "--distance", "0.5"}, "--distance"},
      {{"--out", "x", "--methods", "cells,splats"}, "--methods: 'splats'"},
      {{"--out", "x", "--settings", "n=3 r=1,n=9"}, "--settings: 'n=9'"},
      {{"--out", "x", "--size", "12x"}, "--size: '12x' is not WxH"},
      {{"--out", "x", "--device", "vulkan"}, "--device: 'vulkan' is not one of auto, gpu, lavapipe"},
      {{"--out", "x", "--views", "9"}, "--views"},
      // The scene's cameras replace the orbit views: with them, --views and --distance mean nothing.
      {{"--out", "x", "--scene-cameras", "all"}, "--scene-cameras: the views are a glTF scene's cameras; give the --scene"},
      {{"--out", "x", "--scene-cameras", "all", "--views", "3"}, "excludes"},
      {{"--out", "x", "--scene-cameras", "all", "--distance", "2"}, "excludes"},
      {{"--out", "x", "--frames", "0"}, "--frames"},
      {{"--out", "x", "--time-limit", "-1"}, "--time-limit"},
      {{"--out", "x", "--time-limit", "nan"}, "--time-limit"},
      {{"--out", "x", "--shape", "teapot"}, "--shape"},
      {{"--out", "x", "--shape", "torus", "--methods", "mesh"}, "--methods mesh"},
      {{"--out", "x", "--shape", "torus", "--objects"}, "--objects"},
      {{"--resolutions", "16"}, "--out"},  // required
      // Only tracers past their K range: every row is left out, and the capture failed after opening
      // its device with "--methods: no rows to capture".
      {{"--out", "x", "--resolutions", "600,1024", "--methods", "hermite,trilinear"}, "--resolutions / --methods: no row to capture"},
      // An existing file of the wrong kind: a baked field has no source to re-bake or cast against.
      {{"--out", "x", "--scene", HSDF_TEST_DATA_DIR "/fuzz/hsdf_load_fuzz/sphere_k4_fp32.hsdf"}, "--scene: '"},
  };
  for (const Case& c : cases) {
    const ParseResult r = parse(c.args);
    EXPECT_FALSE(r.options) << c.message;
    EXPECT_NE(r.exitCode, 0) << c.message;
    EXPECT_NE(r.message.find(c.message), std::string::npos) << r.message;
  }
}

// Tricky: trilinear also runs at 2K (capped at 256) and only trilinear does; every label is unique
// (labels name the images); a shape has no mesh row.
TEST(CaptureRows, MethodTimesKTimesSetting) {
  const ParseResult r = parse({"--out", "x", "--resolutions", "32,128"});
  ASSERT_TRUE(r.options);
  const std::vector<RowSpec> rows = buildRows(*r.options);
  std::set<std::string> labels;
  int trilinear = 0, cells = 0;
  for (const RowSpec& row : rows) {
    EXPECT_TRUE(labels.insert(row.label).second) << row.label;
    if (row.method == "trilinear") ++trilinear;
    if (row.method == "cells") ++cells;
    if (row.method != "trilinear" && !row.isMesh()) {
      EXPECT_TRUE(row.resolution == 32 || row.resolution == 128) << row.label;
    }
  }
  EXPECT_EQ(trilinear, 2 * 4);  // K = 32, 64, 128, 256, two normal modes each
  // n in {2, 3} x r in {0, 1}, fp16, no-cull, occlusion, thin and attribute boxes, 8x8, 4x4 and
  // 16x16 tiles and boxes, tiles and boxes of whole cells (the paper's proxy), the certified search
  EXPECT_EQ(cells, 2 * 16);
  EXPECT_TRUE(labels.contains("cells certified K=32"));
  EXPECT_TRUE(labels.contains("cells n=3 r=1 thin K=32"));
  EXPECT_TRUE(labels.contains("cells n=3 r=1 tiles K=32"));
  EXPECT_TRUE(labels.contains("cells n=3 r=1 tiles 4x4 K=128"));
  EXPECT_TRUE(labels.contains("cells n=3 r=1 tiles 16x16 K=128"));
  EXPECT_TRUE(labels.contains("cells n=3 r=1 boxes K=128"));
  EXPECT_TRUE(labels.contains("cells n=3 r=1 boxes whole cells K=32"));
  EXPECT_TRUE(labels.contains("cells n=3 r=1 tiles whole cells K=128"));
  EXPECT_TRUE(labels.contains("cells-runs n=3 r=1 K=32"));
  EXPECT_TRUE(labels.contains("cell-bricks n=3 r=1 fp16 K=32"));
  EXPECT_TRUE(labels.contains("cell-bricks n=3 r=1 no-cull K=32"));
  EXPECT_TRUE(labels.contains("cells n=3 r=1 no-cull K=32"));
  EXPECT_TRUE(labels.contains("cells n=3 r=1 occlusion K=32"));
  EXPECT_TRUE(labels.contains("mesh"));
  EXPECT_TRUE(labels.contains("trilinear central K=256"));
  EXPECT_FALSE(labels.contains("hermite K=256"));

  // --settings keeps the listed cell settings (of both cell methods) and every tracer row.
  const ParseResult some = parse({"--out", "x", "--resolutions", "32", "--settings", "n=3 r=1,certified"});
  ASSERT_TRUE(some.options) << some.message;
  std::set<std::string> kept;
  for (const RowSpec& row : buildRows(*some.options)) kept.insert(row.label);
  EXPECT_EQ(kept, (std::set<std::string>{"mesh", "trilinear central K=32", "trilinear exact K=32", "hermite K=32",
                                         "cells n=3 r=1 K=32", "cells certified K=32", "cells-runs n=3 r=1 K=32",
                                         "cell-bricks n=3 r=1 K=32", "trilinear central K=64", "trilinear exact K=64"}));

  const ParseResult shape = parse({"--out", "x", "--shape", "torus", "--resolutions", "16"});
  ASSERT_TRUE(shape.options);
  for (const RowSpec& row : buildRows(*shape.options)) EXPECT_FALSE(row.isMesh());
}

// Tricky: --lod adds a lod twin of each cell row only (the tracers have no levels), with
// TuningState::lod on and a label of its own; K past 512 keeps the cell rows and drops the dense
// tracers' (their range, tuning.h), instead of failing those rows at bake time. --distance is kept.
TEST(CaptureRows, LodRowsAndLargeK) {
  const ParseResult r = parse({"--out", "x", "--resolutions", "256,1024", "--settings", "n=3 r=1", "--lod", "--distance", "8"});
  ASSERT_TRUE(r.options) << r.message;
  EXPECT_EQ(r.options->distance, 8.0f);
  std::set<std::string> labels;
  for (const RowSpec& row : buildRows(*r.options)) {
    labels.insert(row.label);
    EXPECT_EQ(row.state.lod, row.label.find(" lod ") != std::string::npos) << row.label;
  }
  EXPECT_TRUE(labels.contains("cells n=3 r=1 lod K=256"));
  EXPECT_TRUE(labels.contains("cells n=3 r=1 lod K=1024"));
  EXPECT_TRUE(labels.contains("cells-runs n=3 r=1 lod K=1024"));
  EXPECT_TRUE(labels.contains("hermite K=256"));
  EXPECT_FALSE(labels.contains("hermite K=1024"));
  EXPECT_FALSE(labels.contains("trilinear central K=1024"));
  for (const std::string& label : labels)
    EXPECT_FALSE(label.starts_with("trilinear") && label.find("lod") != std::string::npos) << label;
  const ParseResult off = parse({"--out", "x", "--resolutions", "32"});
  ASSERT_TRUE(off.options);
  for (const RowSpec& row : buildRows(*off.options)) EXPECT_FALSE(row.state.lod) << row.label;
}

}  // namespace
}  // namespace capture
