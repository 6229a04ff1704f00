// The shader statistics table's writer (samples/shader_stats/report.h): roles, CSV columns and
// quoting, the Markdown's columns and refusals, the SPIR-V files no pipeline compiled. No device:
// the rows are made here as the engine records them.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "report.h"

namespace shader_stats {
namespace {

using engine::gpu::StageStatistics;

StageStatistics row(std::string pipeline, std::string stage, std::string shader,
                    std::vector<std::pair<std::string, double>> values, std::string error = {}) {
  return {std::move(pipeline), std::move(stage), std::move(shader), std::move(values), std::move(error)};
}

std::vector<std::string> lines(const std::string& text) {
  std::vector<std::string> result;
  std::size_t start = 0;
  for (std::size_t end; (end = text.find('\n', start)) != std::string::npos; start = end + 1)
    result.push_back(text.substr(start, end - start));
  return result;
}

// Tricky: the role comes from either name: "hermite cells depth counted fp32" says it in the
// pipeline's name, a wireframe pipeline only in its shader's (cells_wire.frag); an early depth
// fix-up says "early" in its shader only.
TEST(ShaderStatsReport, RolesComeFromThePipelineOrItsShaders) {
  EXPECT_EQ(pipelineRole(row("hermite cells depth counted fp32", "fragment", "cells_depth_counted.frag", {})), "counting only");
  EXPECT_EQ(pipelineRole(row("sphere trace wireframe", "fragment", "cells_wire.frag", {})), "debug view");
  EXPECT_EQ(pipelineRole(row("hermite cells depth fix-up", "fragment", "cells_depth_early_fixup.frag", {})),
            "software rasterizers");
  EXPECT_EQ(pipelineRole(row("hermite cells depth fp32", "fragment", "cells_depth.frag", {})), "production");
}

// Tricky: drivers name different statistics per stage (a compute stage may add "LDS size"), so the
// CSV's columns are their union, and a real pipeline name holds a comma ("mesh depth prepass,
// double-sided"): quoted, or every later column shifts.
TEST(ShaderStatsReport, CsvHasEveryStatisticAndQuotesNames) {
  const std::vector<StageStatistics> rows = {
      row("mesh depth prepass, double-sided", "fragment", "mesh_prepass.frag", {{"VGPRs", 8}, {"SGPRs", 16}}),
      row("pyramid", "compute", "depth_pyramid.comp", {{"VGPRs", 12}, {"LDS size", 512}}),
      row("broken", "fragment", "x.frag", {}, "no \"copy\"")};
  const std::vector<std::string> csv = lines(statisticsCsv(rows));
  ASSERT_EQ(csv.size(), 4u);
  EXPECT_EQ(csv[0], "pipeline,stage,shader,role,VGPRs,SGPRs,LDS size,error");
  EXPECT_EQ(csv[1], "\"mesh depth prepass, double-sided\",fragment,mesh_prepass.frag,production,8,16,,");
  EXPECT_EQ(csv[2], "pyramid,compute,depth_pyramid.comp,production,12,,512,");
  EXPECT_EQ(csv[3], "broken,fragment,x.frag,production,,,,\"no \"\"copy\"\"\"");
}

// Tricky: the Markdown keeps ACO's main columns only (registers, spills, scratch, ...) but must
// not come out empty for a driver that names none of them (a native NVIDIA capture): then every
// statistic is a column. A row that could not be compiled says so instead of showing zeros.
TEST(ShaderStatsReport, MarkdownColumnsAndRowsThatWereNotCompiled) {
  const ReportHeader header{"Null hardware (RADV NAVI10)", "llvmpipe", "shader_stats --out x", "abc123"};
  const std::string aco = statisticsMarkdown(
      {row("a", "fragment", "a.frag", {{"Driver pipeline hash", 7}, {"VGPRs", 96}, {"Spilled VGPRs", 0}}),
       row("b", "fragment", "b.frag", {}, "no copy")},
      header, {"unused.frag"});
  EXPECT_NE(aco.find("not timings"), std::string::npos);
  EXPECT_NE(aco.find("`shader_stats --out x` (commit abc123)"), std::string::npos);
  EXPECT_NE(aco.find("| pipeline | stage | shader | role | VGPRs | Spilled VGPRs |\n"), std::string::npos) << aco;
  EXPECT_EQ(aco.find("Driver pipeline hash"), std::string::npos);
  EXPECT_NE(aco.find("| a | fragment | a.frag | production | 96 | 0 |\n"), std::string::npos) << aco;
  EXPECT_NE(aco.find("| b | fragment | b.frag | production | not compiled: no copy |  |\n"), std::string::npos) << aco;
  EXPECT_NE(aco.find("- unused.frag\n"), std::string::npos);
  const std::string other = statisticsMarkdown({row("a", "fragment", "a.frag", {{"Register Count", 40}})}, header, {});
  EXPECT_NE(other.find("| Register Count |"), std::string::npos) << other;
  EXPECT_NE(other.find("| 40 |"), std::string::npos) << other;
  EXPECT_NE(other.find("compiled: none."), std::string::npos) << other;
}

// Tricky: a driver may merge stages into one executable ("a.vert+b.geom"): each of its shaders
// counts as compiled; files other than SPIR-V (the build's .d files) are not shaders.
TEST(ShaderStatsReport, UncompiledShadersAreTheFolderLessWhatTheRowsNamed) {
  const std::filesystem::path folder = std::filesystem::path(::testing::TempDir()) / "shader_stats_report_test";
  std::filesystem::remove_all(folder);
  std::filesystem::create_directories(folder);
  for (const char* file : {"a.vert.spv", "b.frag.spv", "c.comp.spv", "d.frag.spv", "d.frag.d"}) std::ofstream(folder / file) << "x";
  const std::vector<StageStatistics> rows = {row("p", "vertex", "a.vert+b.frag", {}), row("q", "compute", "c.comp", {})};
  EXPECT_EQ(uncompiledShaders(rows, folder), std::vector<std::string>{"d.frag"});
  std::filesystem::remove_all(folder);
}

}  // namespace
}  // namespace shader_stats
