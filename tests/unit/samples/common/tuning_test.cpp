// Typed tuning settings (samples/common/tuning.h): names, the one mapping onto the SDF component,
// and settings files. Each case says what it would catch.
#include <gtest/gtest.h>

#include <filesystem>

#include <fmt/format.h>

#include "engine/core/files.h"
#include "tuning.h"
#include "tuning_fields.h"
#include "tuning_table_values.h"

namespace samples {
namespace {

std::filesystem::path tempFile(const std::string& name) {
  return std::filesystem::temp_directory_path() / ("hsdf_tuning_test_" + name);
}

bool contains(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

// Tricky: the name tables are the only place strings meet methods; a missing or duplicated entry
// would make a method unparseable or print as another.
TEST(Tuning, EveryNameParsesBackToItsValue) {
  for (Method m : allMethods()) EXPECT_EQ(parseMethod(methodName(m)), m);
  // The names of command lines, settings files and scripts, now the module's table and "mesh".
  const std::pair<const char*, Method> names[] = {{"mesh", Method::Mesh},
                                                  {"cells", hsdf::RenderMethod::Cells},
                                                  {"trilinear", hsdf::RenderMethod::TrilinearSphereTrace},
                                                  {"hermite", hsdf::RenderMethod::HermiteSphereTrace},
                                                  {"cells-runs", hsdf::RenderMethod::CellRuns},
                                                  {"cell-bricks", hsdf::RenderMethod::CellBricks}};
  ASSERT_EQ(allMethods().size(), std::size(names)) << "a method without a name here";
  for (const auto& [name, method] : names) {
    EXPECT_EQ(parseMethod(name), method) << name;
    EXPECT_STREQ(methodName(method), name);
  }
  for (hsdf::NormalMode n : {hsdf::NormalMode::Exact, hsdf::NormalMode::CentralDifferences})
    EXPECT_EQ(parseNormalMode(normalModeName(n)), n);
  for (DebugView v : allDebugViews()) EXPECT_EQ(parseDebugView(debugViewName(v)), v);
  const std::pair<const char*, std::uint32_t> views[] = {{"none", DEBUG_VIEW_NONE},   {"normals", DEBUG_VIEW_NORMALS},
                                                         {"depth", DEBUG_VIEW_DEPTH}, {"cells", DEBUG_VIEW_CELLS},
                                                         {"evals", DEBUG_VIEW_EVALS}, {"wireframe", DEBUG_VIEW_WIREFRAME}};
  ASSERT_EQ(allDebugViews().size(), std::size(views)) << "a debug view without a name here";
  for (const auto& [name, value] : views) {
    EXPECT_EQ(parseDebugView(name), DebugView(value)) << name;
    EXPECT_STREQ(debugViewName(DebugView(value)), name);
  }
  for (SplitMode m : {SplitMode::Off, SplitMode::Vertical, SplitMode::Horizontal}) EXPECT_EQ(parseSplitMode(splitModeName(m)), m);
  for (AutoSwitch m : {AutoSwitch::Auto, AutoSwitch::On, AutoSwitch::Off}) EXPECT_EQ(parseAutoSwitch(autoSwitchName(m)), m);
  EXPECT_FALSE(parseMethod("Cells").has_value()) << "names are case-sensitive, as on the command line";
  EXPECT_FALSE(parseNormalMode("").has_value());
}

// Tricky: every tuned field must reach the component, and Method::Mesh must not clobber the
// method the entity already has (the mesh method has no SDF counterpart).
TEST(Tuning, ApplyTuningMapsEveryField) {
  TuningState t;
  t.method = hsdf::RenderMethod::HermiteSphereTrace;
  t.subdivisions = 7;
  t.refineSteps = 4;
  t.normals = hsdf::NormalMode::CentralDifferences;
  t.fp16 = true;
  t.certified = true;
  hsdf::HermiteSdfRenderable r;
  applyTuning(t, r);
  EXPECT_TRUE(r.certified);
  EXPECT_EQ(r.method, hsdf::RenderMethod::HermiteSphereTrace);
  EXPECT_EQ(r.subdivisions, 7u);
  EXPECT_EQ(r.refineSteps, 4u);
  EXPECT_EQ(r.normals, hsdf::NormalMode::CentralDifferences);
  EXPECT_TRUE(r.halfPrecision);
  t.method = hsdf::RenderMethod::TrilinearSphereTrace;
  applyTuning(t, r);
  EXPECT_EQ(r.method, hsdf::RenderMethod::TrilinearSphereTrace);
  t.method = Method::Mesh;
  applyTuning(t, r);
  EXPECT_EQ(r.method, hsdf::RenderMethod::TrilinearSphereTrace);
  t.method = hsdf::RenderMethod::Cells;
  applyTuning(t, r);
  EXPECT_EQ(r.method, hsdf::RenderMethod::Cells);
}

// Tricky: every field differs from its default, so a key that is saved but not loaded (or loaded
// into the wrong field) breaks the equality.
TEST(Tuning, SettingsFileRoundTrip) {
  TuningState t;
  t.method = hsdf::RenderMethod::TrilinearSphereTrace;
  t.resolution = 40;
  t.padding = 3;
  t.subdivisions = 9;
  t.refineSteps = 0;
  t.normals = hsdf::NormalMode::CentralDifferences;
  t.fp16 = true;
  t.debugView = DebugView(DEBUG_VIEW_WIREFRAME);
  t.frontToBack = false;
  t.earlyDepth = AutoSwitch::Off;
  t.certified = true;
  t.cullBricks = false;
  t.cullCells = false;
  t.cullOcclusion = true;  // not the default (off)
  t.proxyBoxes = false;     // not the default (on)
  t.thinBoxes = AutoSwitch::On;
  t.tiles = AutoSwitch::Off;
  t.tileSize = 16;
  t.split = SplitMode::Horizontal;
  t.splitPosition = 0.3f;  // exact in binary and in the JSON text
  t.compareMethod = hsdf::RenderMethod::HermiteSphereTrace;
  t.compareResolution = 48;
  t.compareNormals = hsdf::NormalMode::Exact;
  t.difference = true;
  t.nodeDraw = hsdf::NodeDraw::Triangles;
  t.triangleNodes = {"rock_0_3", "box 2"};
  t.lod = true;
  t.lodPixelsPerCell = 3.5f;  // exact in binary and in the JSON text
  t.traceEpsilon = 0.001953125f;  // 2^-9: exact in binary and in the JSON text
  t.traceMaxSteps = 77;
  t.centralDifferenceStep = 0.25f;
  t.maxRunLength = 5;
  const auto file = tempFile("round_trip.json");
  ASSERT_TRUE(saveTuning(file, t).ok());
  const auto loaded = loadTuning(file);
  ASSERT_TRUE(loaded.ok()) << loaded.error().message;
  EXPECT_TRUE(*loaded == t);
}

// Tricky: early_depth has three values in two JSON types (true / false / "auto"); each must come
// back as itself, and "auto" must be the default a file without the key keeps.
TEST(Tuning, EarlyDepthRoundTripsItsThreeValues) {
  EXPECT_EQ(TuningState{}.earlyDepth, AutoSwitch::Auto);
  const auto file = tempFile("early_depth.json");
  for (AutoSwitch mode : {AutoSwitch::Auto, AutoSwitch::On, AutoSwitch::Off}) {
    TuningState t;
    t.earlyDepth = mode;
    ASSERT_TRUE(saveTuning(file, t).ok());
    const auto text = engine::readTextFile(file);
    ASSERT_TRUE(text.ok());
    const char* expected = mode == AutoSwitch::Auto ? R"("early_depth": "auto")"
                           : mode == AutoSwitch::On ? R"("early_depth": true)"
                                                    : R"("early_depth": false)";
    EXPECT_NE(text->find(expected), std::string::npos) << *text;
    TuningState base;
    base.earlyDepth = mode == AutoSwitch::Off ? AutoSwitch::On : AutoSwitch::Off;  // not what the file says
    const auto loaded = loadTuning(file, base);
    ASSERT_TRUE(loaded.ok()) << loaded.error().message;
    EXPECT_EQ(loaded->earlyDepth, mode) << autoSwitchName(mode);
  }
  TuningState t;
  ASSERT_TRUE(setTuningValue(t, "early_depth", "false").ok());  // a --script line
  EXPECT_EQ(t.earlyDepth, AutoSwitch::Off);
  ASSERT_TRUE(setTuningValue(t, "early_depth", "auto").ok());
  EXPECT_EQ(t.earlyDepth, AutoSwitch::Auto);
}

// Tricky: keys left out keep the base's values (a file may set only the method).
TEST(Tuning, MissingKeysKeepTheBase) {
  const auto file = tempFile("partial.json");
  ASSERT_TRUE(engine::writeTextFile(file, R"({"method": "cells"})").ok());
  TuningState base;
  base.resolution = 33;
  const auto loaded = loadTuning(file, base);
  ASSERT_TRUE(loaded.ok()) << loaded.error().message;
  EXPECT_EQ(loaded->method, hsdf::RenderMethod::Cells);
  EXPECT_EQ(loaded->resolution, 33);
}

// Tricky: each bad value must be refused naming both the file and the key (or the rule broken),
// never silently clamped or ignored.
TEST(Tuning, BadSettingsFilesNameTheKeyAndFile) {
  struct Case {
    const char* text;
    const char* expected;
  };
  const Case cases[] = {
      {R"({"resolution": 5000})", "setting 'resolution': 5000 is outside 2..2048"},
      // The K range follows the method: the dense tracers stop at 512, the limit named.
      {R"({"method": "trilinear", "resolution": 1024})", "--resolution 1024 is outside 2..512 for --method trilinear"},
      {R"({"method": "hermite", "compare_method": "trilinear", "compare_resolution": 600})",
       "--compare-resolution 600 is outside 2..512"},
      {R"({"lod": 1})", "setting 'lod': expected true or false"},
      {R"({"lod_pixels_per_cell": 100})", "setting 'lod_pixels_per_cell': 100 is outside 0.25..64"},
      {R"({"lod_pixels_per_cell": 0.1})", "setting 'lod_pixels_per_cell': 0.1 is outside 0.25..64"},
      {R"({"resolution": 2.5})", "setting 'resolution': expected an integer, got 2.5"},
      {R"({"method": "phong"})", "setting 'method': \"phong\" is not one of mesh, cells, trilinear, hermite"},
      {R"({"normals": 1})", "setting 'normals': 1 is not one of exact, central"},
      {R"({"fp16": "yes"})", "setting 'fp16': expected true or false"},
      {R"({"colour": 1})", "setting 'colour': unknown setting"},
      {R"({"subdivisions": 0})", "setting 'subdivisions': 0 is outside 1..64"},
      {R"({"resolution": 3, "padding": 1})", "--resolution 3 leaves no cells inside --padding 1"},
      {R"([1, 2])", "expected a JSON object of settings"},
      {R"({"method": )", "not valid JSON"},
      {R"({"split": "diagonal"})", "setting 'split': \"diagonal\" is not one of off, vertical, horizontal"},
      {R"({"split_position": 1.0})", "setting 'split_position': 1 is outside 0.05..0.95"},
      {R"({"split_position": "middle"})", "setting 'split_position': expected a number"},
      {R"({"compare_method": "mesh"})", "setting 'compare_method': the compared method must be an SDF method"},
      {R"({"compare_resolution": 1})", "setting 'compare_resolution': 1 is outside 2..2048"},
      {R"({"compare_resolution": 3, "padding": 1})", "--compare-resolution 3 leaves no cells inside --padding 1"},
      {R"({"difference": 1})", "setting 'difference': expected true or false"},
      {R"({"early_depth": "on"})", "setting 'early_depth': expected true, false or \"auto\", got \"on\""},
      {R"({"node_draw": "mesh"})", "setting 'node_draw': \"mesh\" is not one of sdf, triangles"},
      {R"({"triangle_nodes": [1]})", "setting 'triangle_nodes': expected node names, got 1"},
      {R"({"triangle_nodes": ["a", ""]})", "setting 'triangle_nodes': an empty node name"},
      {R"({"triangle_nodes": true})", "setting 'triangle_nodes': expected an array of node names"},
      // In range but not a size the tiles have (4, 8, 16): a rule of its own, named.
      {R"({"tile_size": 6})", "--tile-size 6 is not one of 4, 8, 16"},
      {R"({"tile_size": 32})", "setting 'tile_size': 32 is outside 4..16"},
  };
  const auto file = tempFile("bad.json");
  for (const Case& c : cases) {
    ASSERT_TRUE(engine::writeTextFile(file, c.text).ok());
    const auto loaded = loadTuning(file);
    ASSERT_FALSE(loaded.ok()) << c.text;
    EXPECT_TRUE(contains(loaded.error().message, file.string())) << loaded.error().message;
    EXPECT_TRUE(contains(loaded.error().message, c.expected)) << loaded.error().message;
  }
  const auto missing = loadTuning(tempFile("does_not_exist.json"));
  ASSERT_FALSE(missing.ok());
  EXPECT_TRUE(contains(missing.error().message, "does_not_exist.json")) << missing.error().message;
}

// Tricky: the compared side's K follows the main K (2K) unless set, is capped at the top of the
// range (K 200 would ask for 400), and a compared method of cells draws the main asset (its K);
// n, refinement and fp16 stay shared with the main side.
TEST(Tuning, CompareTuningFollowsTheRuleOfThumb) {
  TuningState t;
  t.resolution = 40;
  t.subdivisions = 5;
  EXPECT_FALSE(comparing(t));
  t.split = SplitMode::Vertical;
  EXPECT_TRUE(comparing(t));
  EXPECT_EQ(effectiveCompareResolution(t), 80);
  t.resolution = 200;
  EXPECT_EQ(effectiveCompareResolution(t), 256);
  t.compareResolution = 24;
  EXPECT_EQ(effectiveCompareResolution(t), 24);
  const TuningState c = compareTuning(t);
  EXPECT_EQ(c.method, hsdf::RenderMethod::TrilinearSphereTrace);
  EXPECT_EQ(c.resolution, 24);
  EXPECT_EQ(c.normals, hsdf::NormalMode::CentralDifferences);
  EXPECT_EQ(c.subdivisions, 5u);
  t.compareMethod = hsdf::RenderMethod::Cells;
  EXPECT_EQ(compareTuning(t).resolution, 200);
  t.split = SplitMode::Off;
  t.difference = true;
  EXPECT_TRUE(comparing(t));
}

// Tricky: a float setting's bounds are floats (0.05f is a hair above the double 0.05), so the
// bounds the error message names, written in a file or a script, were refused: every float key
// must take both ends of its range as text and as JSON, and refuse the next value out.
TEST(Tuning, FloatSettingsTakeTheBoundsTheirMessagesName) {
  struct Case {
    const char* key;
    const char* lo;
    const char* hi;
    const char* below;
    const char* above;
  };
  const Case cases[] = {{"split_position", "0.05", "0.95", "0.049", "0.951"},
                        {"lod_pixels_per_cell", "0.25", "64", "0.249", "64.01"},
                        {"trace_epsilon", "1e-6", "0.1", "9e-7", "0.101"},
                        {"central_difference_step", "0.01", "1", "0.0099", "1.001"}};
  for (const Case& c : cases) {
    for (const char* value : {c.lo, c.hi}) {
      TuningState t;
      EXPECT_TRUE(setTuningValue(t, c.key, value).ok()) << c.key << "=" << value;
      const auto file = tempFile("bounds.json");
      ASSERT_TRUE(engine::writeTextFile(file, fmt::format(R"({{"{}": {}}})", c.key, value)).ok());
      const auto loaded = loadTuning(file);
      EXPECT_TRUE(loaded.ok()) << c.key << ": " << value << ": " << (loaded.ok() ? "" : loaded.error().message);
    }
    for (const char* value : {c.below, c.above}) {
      TuningState t;
      const engine::Status status = setTuningValue(t, c.key, value);
      ASSERT_FALSE(status.ok()) << c.key << "=" << value;
      EXPECT_TRUE(contains(status.error().message, "is outside")) << status.error().message;
    }
  }
}

// Tricky: script values arrive as text: "32" must become a number, "true" a bool and "cells" a
// name, through the same checks as a settings file; a refused value must leave the state as it was
// (the panel and the running scene keep the last good tuning).
TEST(Tuning, SetTuningValueFromText) {
  TuningState t;
  ASSERT_TRUE(setTuningValue(t, "resolution", "32").ok());
  ASSERT_TRUE(setTuningValue(t, "fp16", "true").ok());
  ASSERT_TRUE(setTuningValue(t, "method", "trilinear").ok());
  ASSERT_TRUE(setTuningValue(t, "normals", "central").ok());
  ASSERT_TRUE(setTuningValue(t, "split", "vertical").ok());
  ASSERT_TRUE(setTuningValue(t, "split_position", "0.25").ok());
  ASSERT_TRUE(setTuningValue(t, "compare_resolution", "0").ok());
  ASSERT_TRUE(setTuningValue(t, "node_draw", "triangles").ok());
  ASSERT_TRUE(setTuningValue(t, "triangle_nodes", "bunny_0_1,torus_2_2").ok());
  EXPECT_EQ(t.nodeDraw, hsdf::NodeDraw::Triangles);
  EXPECT_EQ(t.triangleNodes, (std::vector<std::string>{"bunny_0_1", "torus_2_2"}));
  EXPECT_EQ(t.split, SplitMode::Vertical);
  EXPECT_EQ(t.splitPosition, 0.25f);
  EXPECT_EQ(t.compareResolution, 0);
  EXPECT_EQ(t.resolution, 32);
  EXPECT_TRUE(t.fp16);
  EXPECT_EQ(t.method, hsdf::RenderMethod::TrilinearSphereTrace);
  EXPECT_EQ(t.normals, hsdf::NormalMode::CentralDifferences);

  const TuningState before = t;
  struct Case {
    const char* key;
    const char* value;
    const char* expected;
  };
  const Case cases[] = {
      {"resolution", "600", "--resolution 600 is outside 2..512 for --method trilinear"},
      {"resolution", "big", "setting 'resolution': expected an integer, got \"big\""},
      {"fp16", "1", "setting 'fp16': expected true or false, got 1"},
      {"method", "true", "setting 'method': true is not one of"},
      {"resolution", "3", "--resolution 3 leaves no cells inside --padding 1"},
      {"colour", "red", "setting 'colour': unknown setting"},
      {"node_draw", "cells", "setting 'node_draw': \"cells\" is not one of sdf, triangles"},
      {"triangle_nodes", "a,,b", "setting 'triangle_nodes': an empty node name"},
  };
  for (const Case& c : cases) {
    const engine::Status status = setTuningValue(t, c.key, c.value);
    ASSERT_FALSE(status.ok()) << c.key << "=" << c.value;
    EXPECT_TRUE(contains(status.error().message, c.expected)) << status.error().message;
    EXPECT_TRUE(t == before) << c.key << "=" << c.value << " changed the state although it was refused";
  }
}

// Tricky: every reader, writer and option is made from the table's rows; a row that shares its
// member, key, option or label with another would read or write the other's setting (the walks
// below would then test one member twice and the other never).
TEST(TuningTable, EveryRowHasItsOwnMemberKeyOptionAndLabel) {
  const auto rows = tuningFields();
  for (std::size_t i = 0; i < rows.size(); ++i) {
    for (std::size_t j = i + 1; j < rows.size(); ++j) {
      EXPECT_FALSE(rows[i].member == rows[j].member) << rows[i].key << " and " << rows[j].key;
      EXPECT_STRNE(rows[i].key, rows[j].key);
      EXPECT_STRNE(rows[i].option, rows[j].option);
      EXPECT_STRNE(rows[i].label, rows[j].label);
    }
    EXPECT_EQ(findTuningField(rows[i].key), &rows[i]);
    EXPECT_FALSE(rows[i].help.empty()) << rows[i].key << ": the option's help and the panel's tooltip";
  }
}

// Tricky: a row whose reader or writer loses its value (an auto switch written as a bool, a float
// as an int, a list as its first name) breaks the equality; the value changed is derived from the
// row, so a new row is tested without an edit here.
TEST(TuningTable, EveryFieldRoundTripsThroughASettingsFile) {
  const auto file = tempFile("table_round_trip.json");
  for (const TuningField& field : tuningFields()) {
    TuningState t = testing::walkBase();
    const std::string text = testing::otherValueText(field, t);
    ASSERT_TRUE(setTuningFromText(field, text, t).ok()) << field.key << " " << text;
    ASSERT_FALSE(sameTuningValue(field, t, testing::walkBase())) << field.key << ": " << text << " is its default";
    ASSERT_TRUE(validateTuning(t).ok()) << field.key << " " << text << ": " << validateTuning(t).error().message;
    ASSERT_TRUE(saveTuning(file, t).ok());
    const auto loaded = loadTuning(file);
    ASSERT_TRUE(loaded.ok()) << field.key << ": " << loaded.error().message;
    EXPECT_TRUE(*loaded == t) << field.key << " = " << text << " came back as " << tuningValueText(field, *loaded);
  }
}

// Tricky: every number refuses the values just past both ends of its range, in a file and in a
// --script line, naming its key; every field refuses a value of no kind it takes (a JSON object).
TEST(TuningTable, EveryFieldRefusesValuesOutsideItsRangeNamingItsKey) {
  const auto file = tempFile("table_refused.json");
  const auto refusedNaming = [&file](const TuningField& field, const std::string& json, const std::string& why) {
    ASSERT_TRUE(engine::writeTextFile(file, fmt::format(R"({{"{}": {}}})", field.key, json)).ok());
    const auto loaded = loadTuning(file);
    ASSERT_FALSE(loaded.ok()) << field.key << ": " << json << " was taken";
    const std::string named = fmt::format("setting '{}': ", field.key);
    EXPECT_TRUE(contains(loaded.error().message, named + why)) << loaded.error().message;
  };
  for (const TuningField& field : tuningFields()) {
    refusedNaming(field, R"({"a": 1})", "");
    if (tuningKind(field) == TuningKind::Name) refusedNaming(field, R"("no-such-name")", "");
    if (tuningKind(field) != TuningKind::Number) continue;
    for (const std::string& value : {testing::belowRangeText(field), testing::aboveRangeText(field)}) {
      refusedNaming(field, value, value + " is outside");
      TuningState t = testing::walkBase();
      const engine::Status status = setTuningValue(t, field.key, value);
      ASSERT_FALSE(status.ok()) << field.key << "=" << value;
      EXPECT_TRUE(contains(status.error().message, fmt::format("setting '{}': {} is outside", field.key, value)))
          << status.error().message;
    }
  }
}

}  // namespace
}  // namespace samples
