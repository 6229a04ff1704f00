#include "report.h"

#include <algorithm>
#include <set>
#include <sstream>

#include <fmt/format.h>

namespace shader_stats {
namespace {

using engine::gpu::StageStatistics;

bool has(const std::string& text, const char* part) { return text.find(part) != std::string::npos; }

// RADV / ACO's names for what bounds a shader's occupancy and cost, in the table's order.
const std::vector<std::string>& preferredColumns() {
  static const std::vector<std::string> columns = {"VGPRs", "SGPRs", "Spilled VGPRs", "Spilled SGPRs", "Scratch size",
                                                   "Subgroups per SIMD", "Instructions", "Code size", "Latency",
                                                   "Inverse Throughput"};
  return columns;
}

std::vector<std::string> allColumns(const std::vector<StageStatistics>& rows) {
  std::vector<std::string> columns;
  for (const StageStatistics& row : rows)
    for (const auto& [name, value] : row.values)
      if (std::find(columns.begin(), columns.end(), name) == columns.end()) columns.push_back(name);
  return columns;
}

std::vector<std::string> markdownColumns(const std::vector<StageStatistics>& rows) {
  const std::vector<std::string> all = allColumns(rows);
  std::vector<std::string> chosen;
  for (const std::string& column : preferredColumns())
    if (std::find(all.begin(), all.end(), column) != all.end()) chosen.push_back(column);
  return chosen.empty() ? all : chosen;
}

std::string csvField(const std::string& text) {
  if (text.find_first_of(",\"\n") == std::string::npos) return text;
  std::string quoted = "\"";
  for (const char c : text) quoted += c == '"' ? std::string("\"\"") : std::string(1, c);
  return quoted + "\"";
}

std::string number(double value) { return fmt::format("{:g}", value); }

std::string cell(const StageStatistics& row, const std::string& column) {
  const auto value = row.value(column);
  return value ? number(*value) : "";
}

}  // namespace

std::string pipelineRole(const StageStatistics& row) {
  const std::string names = row.pipeline + " " + row.shader;
  if (has(names, "counted")) return "counting only";
  if (has(names, "wire") || has(names, "debug")) return "debug view";
  if (has(names, "early")) return "software rasterizers";
  return "production";
}

std::vector<std::string> uncompiledShaders(const std::vector<StageStatistics>& rows, const std::filesystem::path& folder) {
  std::set<std::string> compiled;
  for (const StageStatistics& row : rows) {
    std::stringstream shaders(row.shader);
    for (std::string shader; std::getline(shaders, shader, '+');) compiled.insert(shader);
  }
  std::vector<std::string> missing;
  std::error_code ec;
  for (const auto& entry : std::filesystem::directory_iterator(folder, ec))
    if (entry.path().extension() == ".spv" && !compiled.contains(entry.path().stem().string()))
      missing.push_back(entry.path().stem().string());
  std::sort(missing.begin(), missing.end());
  return missing;
}

std::string statisticsCsv(const std::vector<StageStatistics>& rows) {
  const std::vector<std::string> columns = allColumns(rows);
  std::string csv = "pipeline,stage,shader,role";
  for (const std::string& column : columns) csv.append(",").append(csvField(column));
  csv += ",error\n";
  for (const StageStatistics& row : rows) {
    csv.append(csvField(row.pipeline)).append(",").append(row.stage).append(",").append(csvField(row.shader));
    csv.append(",").append(pipelineRole(row));
    for (const std::string& column : columns) csv.append(",").append(cell(row, column));
    csv.append(",").append(csvField(row.error)).append("\n");
  }
  return csv;
}

std::string statisticsMarkdown(const std::vector<StageStatistics>& rows, const ReportHeader& header,
                               const std::vector<std::string>& uncompiled) {
  std::string md = fmt::format("# Shader compiler statistics: {}\n\n", header.device);
  md += fmt::format("Command: `{}` (commit {}); frames drawn on {}.\n\n", header.commandLine, header.commit, header.rendering);
  md += fmt::format(
      "What the shader compiler made of every pipeline the engine built, for {}: registers, spills, scratch "
      "memory, instructions and the compiler's own static estimates. These are compiler statistics, **not "
      "timings**: nothing ran. Fewer VGPRs allow more subgroups per SIMD (occupancy), which hides memory "
      "latency on any GPU. All statistics are in `shader_stats.csv`.\n\n",
      header.device);
  const std::vector<std::string> columns = markdownColumns(rows);
  md += "| pipeline | stage | shader | role |";
  for (const std::string& column : columns) md.append(" ").append(column).append(" |");
  md += "\n|---|---|---|---|";
  for (std::size_t i = 0; i < columns.size(); ++i) md += "---|";
  md += "\n";
  for (const StageStatistics& row : rows) {
    md += fmt::format("| {} | {} | {} | {} |", row.pipeline, row.stage, row.shader, pipelineRole(row));
    if (!row.error.empty()) md += fmt::format(" not compiled: {} |", row.error);
    for (std::size_t i = row.error.empty() ? 0 : 1; i < columns.size(); ++i)
      md.append(" ").append(row.error.empty() ? cell(row, columns[i]) : std::string()).append(" |");
    md += "\n";
  }
  md += "\nSPIR-V files no pipeline of this run compiled";
  md += uncompiled.empty() ? ": none.\n" : " (their features need what the rendering device lacks, or no frame chose them):\n\n";
  for (const std::string& shader : uncompiled) md.append("- ").append(shader).append("\n");
  return md;
}

}  // namespace shader_stats
