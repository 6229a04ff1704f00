#include "report.h"

#include <algorithm>
#include <cmath>
#include <functional>
#include <map>
#include <optional>

#include <fmt/format.h>

#include "charts.h"
#include "engine/core/files.h"

namespace capture {
namespace {

// The paper's table (bunny, AMD RX 5700, full HD): ms and approximate stored scalars.
struct PaperRow {
  int k;
  double trilinearMs, hermiteMs, cellsMs;
  const char *trilinearScalars, *hermiteScalars, *cellsScalars;
};
constexpr PaperRow kPaper[] = {{16, 0.72, 2.90, 1.48, "4k", "16k", "20k"},
                               {32, 0.76, 2.80, 1.47, "32k", "130k", "80k"},
                               {64, 0.90, 2.95, 1.69, "260k", "1M", "310k"},
                               {128, 1.06, 2.96, 3.45, "2M", "8.4M", "1.3M"}};

const PaperRow* paperRow(int k) {
  for (const PaperRow& row : kPaper)
    if (row.k == k) return &row;
  return nullptr;
}

std::string csvEscape(const std::string& s) {
  if (s.find_first_of(",\"\n") == std::string::npos) return s;
  std::string out = "\"";
  for (char c : s) out += c == '"' ? std::string("\"\"") : std::string(1, c);
  return out + "\"";
}

std::string jsonEscape(const std::string& s) {
  std::string out;
  for (char c : s) {
    if (c == '"' || c == '\\') out += '\\', out += c;
    else if (c == '\n') out += "\\n";
    else if (static_cast<unsigned char>(c) < 0x20) out += fmt::format("\\u{:04x}", int(c));
    else out += c;
  }
  return out;
}

// 3 significant digits in the largest unit that keeps the value below 1000 when rounded (it printed
// "1.3e+02M" for 130 million and "1e+03k" just below a million).
std::string scalars(std::uint64_t n) {
  double value = double(n);
  const char* unit = "";
  for (const char* next : {"k", "M", "G"}) {
    if (value < 999.5) break;
    value /= 1000.0;
    unit = next;
  }
  return *unit ? fmt::format("{:.3g}{}", value, unit) : std::to_string(n);
}

// The row of this run compared in the paper's column `method` at K (paperColumn rows).
const RowResult* paperColumnRow(const std::vector<RowResult>& rows, const std::string& method, int k) {
  for (const RowResult& r : rows)
    if (r.ok && r.spec.paperColumn && r.spec.method == method && r.spec.resolution == k) return &r;
  return nullptr;
}

const RowResult* findRow(const std::vector<RowResult>& rows, const std::function<bool(const RowSpec&)>& match) {
  for (const RowResult& r : rows)
    if (r.ok && match(r.spec)) return &r;
  return nullptr;
}

std::string ratio(const RowResult* a, const RowResult* b) {
  if (!a || !b || b->gpuMsMedian <= 0.0) return "–";
  return fmt::format("{:.2f}", a->gpuMsMedian / b->gpuMsMedian);
}

double perCovered(double count, const RowResult& r, std::uint32_t views) {
  const double covered = double(r.quality.coveredPixels) / std::max(1u, views);
  return covered > 0.0 ? count / covered : 0.0;
}

// Which part of the frame keeps `cells` above `factor` x `other`: the pass with the larger excess
// over its share of the budget, and the device-independent work counts of both.
std::string holdsBack(const RowResult& cells, const RowResult& other, double factor, const RunInfo& info) {
  const double prepassExcess = cells.prepassMs - factor * other.prepassMs;
  const double shadingExcess = cells.shadingMs - factor * other.shadingMs;
  std::string s = fmt::format(
      "needs {:.1f} ms less ({:.2f}x over); prepass {:.1f} ms vs budget {:.1f} ms, shading {:.1f} ms vs budget "
      "{:.1f} ms: the **{}** holds it back",
      cells.gpuMsMedian - factor * other.gpuMsMedian, cells.gpuMsMedian / (factor * other.gpuMsMedian),
      cells.prepassMs, factor * other.prepassMs, cells.shadingMs, factor * other.shadingMs,
      prepassExcess >= shadingExcess ? "prepass" : "shading pass");
  if (info.pipelineStatistics)
    s += fmt::format("; prepass fragments per covered pixel {:.2f} vs {:.2f}, vertex invocations {:.0f} vs {:.0f}",
                     perCovered(cells.prepassFsInvocations, cells, info.views),
                     perCovered(other.prepassFsInvocations, other, info.views), cells.vsInvocations, other.vsInvocations);
  s += fmt::format(", evaluations per covered pixel {:.1f} vs {:.1f}", cells.quality.evalsMean, other.quality.evalsMean);
  return s;
}

std::vector<int> resolutionsOf(const std::vector<RowResult>& rows) {
  std::vector<int> ks;
  for (const RowResult& r : rows)
    if (!r.spec.isMesh() && std::find(ks.begin(), ks.end(), r.spec.resolution) == ks.end()) ks.push_back(r.spec.resolution);
  std::sort(ks.begin(), ks.end());
  return ks;
}

void paperTable(std::string& md, const std::vector<RowResult>& rows) {
  md += "## The paper's table beside this run\n\n"
        "GPU ms per frame (median over views and frames) and stored scalars. Trilinear = sphere tracing with "
        "central-difference normals, Hermite = dense Hermite sphere tracing, cells = Hermite cells n=3, one "
        "refinement, fp32. Paper: AMD RX 5700, 1920x1080.\n\n"
        "| K | trilinear | Hermite ST | cells | cells / Hermite | cells / trilinear | paper trilinear | paper Hermite | "
        "paper cells | paper cells / Hermite | paper cells / trilinear |\n"
        "|---|---|---|---|---|---|---|---|---|---|---|\n";
  for (int k : resolutionsOf(rows)) {
    const RowResult* t = paperColumnRow(rows, "trilinear", k);
    const RowResult* h = paperColumnRow(rows, "hermite", k);
    const RowResult* c = paperColumnRow(rows, "cells", k);
    if (!h && !c) continue;  // a 2K-only trilinear resolution
    auto cell = [](const RowResult* r) {
      return r ? fmt::format("{:.2f} ms ({})", r->gpuMsMedian, scalars(r->storedScalars)) : std::string("–");
    };
    md += fmt::format("| {} | {} | {} | {} | {} | {} |", k, cell(t), cell(h), cell(c), ratio(c, h), ratio(c, t));
    if (const PaperRow* p = paperRow(k))
      md += fmt::format(" {} ms ({}) | {} ms ({}) | {} ms ({}) | {:.2f} | {:.2f} |\n", p->trilinearMs, p->trilinearScalars,
                        p->hermiteMs, p->hermiteScalars, p->cellsMs, p->cellsScalars, p->cellsMs / p->hermiteMs,
                        p->cellsMs / p->trilinearMs);
    else
      md += " – | – | – | – | – |\n";
  }
  md += "\n";
}

// The n=3 r=1 fp32 row of a cell method ("cells", "cells-runs", "cell-bricks"), the one the targets judge.
const RowResult* cellTargetRow(const std::vector<RowResult>& rows, const std::string& method, int k) {
  return findRow(rows, [&](const RowSpec& s) {
    return s.method == method && s.resolution == k && s.subdivisions == 3 && s.refine == 1 && !s.fp16 &&
           !s.state.certified;
  });
}

// Issues 13 and 20: the targets apply to each Hermite-cell variant, the paper's `cells`, `cells-runs`
// and `cell-bricks`.
const char* const kCellMethods[] = {"cells", "cells-runs", "cell-bricks"};

void targets(std::string& md, const std::vector<RowResult>& rows, const RunInfo& info) {
  md += "## Targets (issues 10 and 13; ratios within this run)\n\n";
  auto mark = [](bool ok) { return ok ? "met" : "**missed**"; };
  for (const char* method : kCellMethods)
    for (int k : resolutionsOf(rows)) {
      const RowResult* c = cellTargetRow(rows, method, k);
      const RowResult* h = paperColumnRow(rows, "hermite", k);
      if (!c || !h) continue;
      // Issue 20: at most 0.5x up to K = 128, at most 1.0x from K = 256 on.
      const double limit = k >= 256 ? 1.0 : 0.5;
      const double r = c->gpuMsMedian / h->gpuMsMedian;
      md += fmt::format("- K={}: {} n=3 r=1 at most {:.1f}x dense Hermite ST: {:.2f}x, {}", k, method, limit, r,
                        mark(r <= limit));
      md += r <= limit ? "\n" : " — " + holdsBack(*c, *h, limit, info) + "\n";
    }
  for (const char* method : kCellMethods)
  for (int k : resolutionsOf(rows)) {
    const RowResult* c = cellTargetRow(rows, method, k);
    const RowResult* t = paperColumnRow(rows, "trilinear", k);
    if (!c || !t) continue;
    const double r = c->gpuMsMedian / t->gpuMsMedian;
    md += fmt::format("- K={}: {} within 1.5x of trilinear (central) at the same K: {:.2f}x, {}", k, method, r, mark(r <= 1.5));
    md += r <= 1.5 ? "\n" : " — " + holdsBack(*c, *t, 1.5, info) + "\n";
    // Equal quality: the lowest trilinear resolution (either normal mode) whose mean normal error
    // is at most the cells'.
    const RowResult* equal = nullptr;
    for (const RowResult& row : rows)
      if (row.ok && row.spec.method == "trilinear" && row.quality.normalErrorMean <= c->quality.normalErrorMean &&
          (!equal || row.gpuMsMedian < equal->gpuMsMedian))
        equal = &row;
    if (!equal) {
      md += fmt::format("- K={}: {} ({:.3f} deg) no slower than trilinear at equal normal error: no trilinear row "
                        "captured reaches that error\n",
                        k, method, c->quality.normalErrorMean);
      continue;
    }
    const double re = c->gpuMsMedian / equal->gpuMsMedian;
    md += fmt::format("- K={}: {} ({:.3f} deg) no slower than the fastest trilinear row at equal or lower normal "
                      "error ({}, {:.3f} deg): {:.2f}x, {}",
                      k, method, c->quality.normalErrorMean, equal->spec.label, equal->quality.normalErrorMean, re, mark(re <= 1.0));
    md += re <= 1.0 ? "\n" : " — " + holdsBack(*c, *equal, 1.0, info) + "\n";
  }
  for (int k : resolutionsOf(rows)) {
    const RowResult* full = paperColumnRow(rows, "cells", k);
    const RowResult* half = findRow(rows, [&](const RowSpec& s) {
      return s.method == "cells" && s.fp16 && s.resolution == k && s.subdivisions == 3 && s.refine == 1;
    });
    if (!full || !half) continue;
    const double bytes = double(half->storedBytes) / double(full->storedBytes);
    const double worse = half->quality.normalErrorMean - full->quality.normalErrorMean;
    md += fmt::format("- K={}: fp16 cells at most half the bytes of fp32 ({:.3f}x, {}) with a mean normal error at most "
                      "0.1 deg worse ({:+.4f} deg, {})\n",
                      k, bytes, mark(bytes <= 0.5), worse, mark(worse <= 0.1));
  }
  md += "\n";
}

// Issue 20's device-independent counts for the cell variants: on lavapipe the pipeline statistics
// count fragments before the depth test, so only boxes that are never drawn lower the first one.
void countTargets(std::string& md, const std::vector<RowResult>& rows, const RunInfo& info) {
  if (!info.pipelineStatistics) return;
  md += "## Count targets (issue 20; pipeline statistics, any device)\n\n"
        "| row | prepass FS / covered px (target <= 3) | boxes / view | prepass VS / box (target <= 8) | evaluations "
        "/ covered px | tile entries read / covered px | tile entries ray-box tested / covered px | tile mask words "
        "read / covered px |\n"
        "|---|---|---|---|---|---|---|---|\n";
  // Every setting of every cell method (thin boxes, no-cull, fp16, ...), not only the target rows.
  for (const char* method : kCellMethods)
    for (int k : resolutionsOf(rows))
      for (const RowResult& c : rows) {
        if (!c.ok || c.spec.method != method || c.spec.resolution != k || c.boxes <= 0.0) continue;
        const bool tiled = c.quality.tileEntriesWalked > 0.0;  // the tiles' list walk (cell_tiles_depth.glsl)
        const auto tileColumn = [&](double value) { return tiled ? fmt::format("{:.1f}", value) : std::string("–"); };
        md += fmt::format("| {} | {:.2f} | {:.0f} | {:.2f} | {:.1f} | {} | {} | {} |\n", c.spec.label,
                          perCovered(c.prepassFsInvocations, c, info.views), c.boxes, c.prepassVsInvocations / c.boxes,
                          c.quality.evalsMean, tileColumn(c.quality.tileEntriesWalked),
                          tileColumn(c.quality.tileEntriesTested), tileColumn(c.quality.tileMaskWordsRead));
      }
  md += "\n";
}

void allRows(std::string& md, const std::vector<RowResult>& rows, const RunInfo& info) {
  md += "## Every row\n\n"
        "Times: median (p95) over views x timed frames; passes are medians. Work (device-independent): fragment "
        "shader invocations per frame in the prepass and the shading pass, vertex shader invocations (pipeline "
        "statistics), root-search evaluations: every pixel's (misses included) per covered pixel, then the covered "
        "pixels' own p95. Quality against the ground truth: "
        "coverage mismatch in pixels per view, normal error mean / p95 in degrees, depth error mean relative to the "
        "bounding-box diagonal. Out of steps: sphere-tracing rays per view that reached the step limit (drawn as "
        "misses; should be 0).\n\n"
        "| row | GPU ms | prepass ms | shading ms | FS prepass | FS shading | VS | evals/px | scalars | bytes | cells | "
        "coverage | normal err (deg) | depth err | out of steps | image |\n"
        "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|\n";
  for (const RowResult& r : rows) {
    if (!r.ok) {
      md += fmt::format("| {} | failed: {} |\n", r.spec.label, r.error);
      continue;
    }
    const std::string stats = info.pipelineStatistics
                                  ? fmt::format("{:.0f} | {:.0f} | {:.0f}", r.prepassFsInvocations, r.shadingFsInvocations,
                                                r.vsInvocations)
                                  : std::string("– | – | –");
    md += fmt::format("| {} | {:.2f} ({:.2f}) | {:.2f} | {:.2f} | {} | {:.1f} / {:.0f} | {} | {} | {} | {:.1f} | {:.3f} / "
                      "{:.3f} | {:.2e} | {:.1f} | [png]({}) |\n",
                      r.spec.label, r.gpuMsMedian, r.gpuMsP95, r.prepassMs, r.shadingMs, stats, r.quality.evalsMean,
                      r.quality.evalsP95, r.storedScalars, r.storedBytes, r.cells, r.quality.coverageMismatch,
                      r.quality.normalErrorMean, r.quality.normalErrorP95, r.quality.depthErrorMean,
                      r.quality.raysOutOfSteps, r.image);
  }
  md += "\n";
}

// The median of every named GPU scope per row: where the frame's time goes beyond the two passes
// (the features' compute work in "prepare": the cells' culling and tiling) and within them.
void passTable(std::string& md, const std::vector<RowResult>& rows) {
  std::vector<std::string> names;  // the union of the rows' scopes, in the order first seen
  for (const RowResult& r : rows)
    for (const auto& [name, ms] : r.passMs)
      if (std::find(names.begin(), names.end(), name) == names.end()) names.push_back(name);
  if (names.empty()) return;  // a device without timestamps
  md += "## GPU time per named scope\n\n"
        "Median ms over views x timed frames of each scope the frame recorded (Renderer::lastTimings; nested "
        "scopes are inside the one before them: \"cells culling\" and \"cells tiling\" inside \"prepare\", "
        "\"cells prepass\" inside \"depth prepass\"). –: the row's frames did not record it.\n\n| row |";
  for (const std::string& name : names) md += " " + name + " |";
  md += "\n|---|";
  for (std::size_t i = 0; i < names.size(); ++i) md += "---|";
  md += "\n";
  for (const RowResult& r : rows) {
    if (!r.ok) continue;
    md += "| " + r.spec.label + " |";
    for (const std::string& name : names) {
      auto it = std::find_if(r.passMs.begin(), r.passMs.end(), [&](const auto& p) { return p.first == name; });
      md += it == r.passMs.end() ? std::string(" – |") : fmt::format(" {:.2f} |", it->second);
    }
    md += "\n";
  }
  md += "\n";
}

// One series per setting (the row label without K), x and y picked from each row.
Chart chartOf(const std::vector<RowResult>& rows, const std::function<glm::dvec2(const RowResult&)>& point,
              bool includeMesh) {
  Chart chart;
  std::map<std::string, std::size_t> index;
  for (const RowResult& r : rows) {
    if (!r.ok || (r.spec.isMesh() && !includeMesh)) continue;
    const std::string name = r.spec.label.substr(0, r.spec.label.rfind(" K="));
    if (!index.contains(name)) {
      index[name] = chart.series.size();
      chart.series.push_back({name, seriesColor(chart.series.size()), {}});
    }
    chart.series[index[name]].points.push_back(point(r));
  }
  return chart;
}

engine::Status chartSection(std::string& md, const std::filesystem::path& folder, const std::string& file,
                            const std::string& title, const Chart& chart) {
  ENGINE_TRY(writeChart(folder / file, chart));
  md += "### " + title + "\n\n![" + title + "](" + file + ")\n\nLegend, left to right:";
  for (const ChartSeries& s : chart.series) md += fmt::format(" <span style=\"color:{0}\">■</span> {1} ({0});", colorHex(s.color), s.name);
  md += "\n\n";
  return {};
}

}  // namespace

engine::Status writeCsv(const std::filesystem::path& path, const RunInfo& info, const std::vector<RowResult>& rows) {
  std::string csv =
      "method,K,subdivisions,refinement,normals,width,height,views,frames,gpu_ms_median,gpu_ms_p95,prepass_ms,"
      "shading_ms,fs_invocations,evals_per_pixel_mean,evals_per_pixel_p95,stored_scalars,stored_bytes,cells,"
      "coverage_mismatch,normal_err_mean_deg,normal_err_p95_deg,depth_err_mean,rays_out_of_steps,evals_covered_mean,"
      "device,label\n";
  for (const RowResult& r : rows) {
    const RowSpec& s = r.spec;
    csv += fmt::format("{},{},{},{},{},{},{},{},{},", s.method, s.resolution, s.subdivisions, s.refine, s.normalsName(),
                       info.width, info.height, info.views, info.frames);
    if (r.ok)
      csv += fmt::format("{:.4f},{:.4f},{:.4f},{:.4f},{:.0f},{:.3f},{:.0f},{},{},{},{:.2f},{:.5f},{:.5f},{:.4e},{:.1f},{:.3f},",
                         r.gpuMsMedian, r.gpuMsP95, r.prepassMs, r.shadingMs, r.fsInvocations, r.quality.evalsMean,
                         r.quality.evalsP95, r.storedScalars, r.storedBytes, r.cells, r.quality.coverageMismatch,
                         r.quality.normalErrorMean, r.quality.normalErrorP95, r.quality.depthErrorMean,
                         r.quality.raysOutOfSteps, r.quality.evalsCoveredMean);
    else
      csv += ",,,,,,,,,,,,,,,,";  // a failed row: no numbers (the capture exits non-zero)
    // The row's label last: the columns before it do not tell apart the variants of one method and K
    // (culling, tiles, thin boxes, certified, fp16, levels of detail).
    csv += csvEscape(info.device) + "," + csvEscape(s.label) + "\n";
  }
  return engine::writeTextFile(path, csv);
}

namespace {

std::string partName(const RunInfo& info, std::int32_t part) {
  return part >= 0 && std::size_t(part) < info.partNames.size() ? info.partNames[std::size_t(part)]
                                                                 : fmt::format("object {}", part);
}

bool hasObjects(const RowResult& r) { return r.ok && r.parts.size() >= 2; }

// Per row of a scene: how the objects' quality spreads, and the worst object by normal error and
// by missed pixels (objects.csv has every object).
void objectsSection(std::string& md, const std::vector<RowResult>& rows, const RunInfo& info) {
  if (std::none_of(rows.begin(), rows.end(), hasObjects)) return;
  md += "## Quality per object\n\nEach object's pixels are those where the ground truth hits it (objects.csv has "
        "every object of every row). Normal error in degrees; missed px: the truth hits the object and the row draws "
        "nothing there, per view.\n\n| row | objects | normal err mean: median / worst | normal err p95: median / "
        "worst (object) | missed px: worst (object, of its px) |\n|---|---|---|---|---|\n";
  for (const RowResult& r : rows) {
    if (!hasObjects(r)) continue;
    std::vector<double> means, p95s;
    for (const PartQuality& p : r.parts) means.push_back(p.normalErrorMean), p95s.push_back(p.normalErrorP95);
    const auto byP95 = std::max_element(r.parts.begin(), r.parts.end(), [](const PartQuality& a, const PartQuality& b) {
      return a.normalErrorP95 < b.normalErrorP95;
    });
    const auto byMissed = std::max_element(r.parts.begin(), r.parts.end(), [](const PartQuality& a, const PartQuality& b) {
      return a.missedPixels < b.missedPixels;
    });
    md += fmt::format("| {} | {} | {:.3f} / {:.3f} | {:.3f} / {:.3f} ({}) | {:.1f} ({}, of {:.1f}) |\n", r.spec.label,
                      r.parts.size(), percentile(means, 0.5), *std::max_element(means.begin(), means.end()),
                      percentile(p95s, 0.5), byP95->normalErrorP95, partName(info, byP95->part), byMissed->missedPixels,
                      partName(info, byMissed->part), byMissed->truthPixels);
  }
  md += "\n";
}

}  // namespace

engine::Status writeObjectsCsv(const std::filesystem::path& path, const RunInfo& info, const std::vector<RowResult>& rows) {
  if (std::none_of(rows.begin(), rows.end(), hasObjects)) return {};
  std::string csv = "row,object,truth_px,missed_px,normal_err_mean_deg,normal_err_p95_deg,depth_err_mean\n";
  for (const RowResult& r : rows) {
    if (!hasObjects(r)) continue;
    for (const PartQuality& p : r.parts)
      csv += fmt::format("{},{},{:.1f},{:.1f},{:.5f},{:.5f},{:.4e}\n", csvEscape(r.spec.label), csvEscape(partName(info, p.part)),
                         p.truthPixels, p.missedPixels, p.normalErrorMean, p.normalErrorP95, p.depthErrorMean);
  }
  return engine::writeTextFile(path, csv);
}

namespace {

std::string passesJson(const RowResult& r) {
  std::string json;
  for (const auto& [name, ms] : r.passMs)
    json += fmt::format("{}\"{}\": {}", json.empty() ? "" : ", ", jsonEscape(name), ms);
  return json;
}

}  // namespace

engine::Status writeJson(const std::filesystem::path& path, const RunInfo& info, const std::vector<RowResult>& rows) {
  std::string json = "{\n";
  json += fmt::format(
      "  \"device\": \"{}\",\n  \"driver\": \"{}\",\n  \"command_line\": \"{}\",\n  \"commit\": \"{}\",\n  \"date\": "
      "\"{}\",\n  \"scene\": \"{}\",\n  \"width\": {},\n  \"height\": {},\n  \"views\": {},\n  \"frames\": {},\n  "
      "\"warmup\": {},\n  \"pipeline_statistics\": {},\n  \"software_rasterizer\": {},\n  \"rows_planned\": {},\n  "
      "\"complete\": {},\n  \"rows\": [\n",
      jsonEscape(info.device), jsonEscape(info.driver), jsonEscape(info.commandLine), jsonEscape(info.commit),
      jsonEscape(info.date), jsonEscape(info.scene), info.width, info.height, info.views, info.frames, info.warmup,
      info.pipelineStatistics, info.softwareRasterizer, info.rowsPlanned, info.complete);
  for (std::size_t i = 0; i < rows.size(); ++i) {
    const RowResult& r = rows[i];
    json += fmt::format(
        "    {{\"label\": \"{}\", \"method\": \"{}\", \"K\": {}, \"subdivisions\": {}, \"refinement\": {}, "
        "\"normals\": \"{}\", \"fp16\": {}, \"ok\": {}, \"error\": \"{}\", \"gpu_ms_median\": {}, \"gpu_ms_p95\": {}, "
        "\"prepass_ms\": {}, \"shading_ms\": {}, \"fs_invocations\": {}, \"prepass_fs_invocations\": {}, "
        "\"shading_fs_invocations\": {}, \"vs_invocations\": {}, \"prepass_vs_invocations\": {}, \"boxes\": {}, "
        "\"clipped_primitives\": {}, \"evals_per_pixel_mean\": "
        "{}, \"evals_per_pixel_p95\": {}, \"evals_covered_mean\": {}, \"tile_entries_read_per_pixel\": {}, \"tile_entries_tested_per_pixel\": {}, "
        "\"tile_mask_words_read_per_pixel\": {}, "
        "\"covered_pixels\": {}, \"stored_scalars\": {}, \"stored_bytes\": {}, "
        "\"cells\": {}, \"coverage_mismatch\": {}, \"normal_err_mean_deg\": {}, \"normal_err_p95_deg\": {}, "
        "\"depth_err_mean\": {}, \"rays_out_of_steps\": {}, \"passes_ms\": {{{}}}, \"image\": \"{}\"}}{}\n",
        jsonEscape(r.spec.label), r.spec.method, r.spec.resolution, r.spec.subdivisions, r.spec.refine,
        r.spec.normalsName(), r.spec.fp16, r.ok, jsonEscape(r.error), r.gpuMsMedian, r.gpuMsP95, r.prepassMs,
        r.shadingMs, r.fsInvocations, r.prepassFsInvocations, r.shadingFsInvocations, r.vsInvocations,
        r.prepassVsInvocations, r.boxes, r.clippedPrimitives, r.quality.evalsMean, r.quality.evalsP95,
        r.quality.evalsCoveredMean, r.quality.tileEntriesWalked,
        r.quality.tileEntriesTested, r.quality.tileMaskWordsRead, r.quality.coveredPixels, r.storedScalars,
        r.storedBytes, r.cells, r.quality.coverageMismatch, r.quality.normalErrorMean, r.quality.normalErrorP95,
        r.quality.depthErrorMean, r.quality.raysOutOfSteps, passesJson(r), jsonEscape(r.image),
        i + 1 < rows.size() ? "," : "");
  }
  json += "  ]\n}\n";
  return engine::writeTextFile(path, json);
}

engine::Status writeMarkdown(const std::filesystem::path& folder, const RunInfo& info, const std::vector<RowResult>& rows) {
  std::string md = "# Perf capture: " + info.scene + "\n\n";
  md += fmt::format("- Command: `{}`\n- Device: {} ({})\n- Commit: {}\n- Date: {}\n- {}x{}, {} views{}, {} warm-up + {} "
                    "timed frames per view\n\n",
                    info.commandLine, info.device, info.driver, info.commit, info.date, info.width, info.height,
                    info.views,
                    info.viewNames.empty() ? std::string(" (orbit views)")
                                           : fmt::format(" (the scene's cameras: {})", fmt::join(info.viewNames, ", ")),
                    info.warmup, info.frames);
  if (info.softwareRasterizer)
    md += "**This device is a software rasterizer (CPU).** Its timings only compare rows of this run with each other; "
          "they say nothing about frame times on a GPU. ";
  md += "The root-search evaluations, the tiles' list counts and the quality and storage columns depend on the "
        "settings, not on the device (the automatic ones, early depth and tiles, choose differently on a software "
        "rasterizer: compare rows of the same settings). The pipeline statistics do depend on the device: a software "
        "rasterizer counts fragments before the depth test, and with the early depth stage the boxes' prepass "
        "counts include its depth fix-up over the objects' screen rectangle. The mesh row's normal error compares "
        "its interpolated vertex normals with the triangles' face normals of the ground truth, so it is not 0 for "
        "the mesh itself. Storage of cells-runs and cell-bricks counts the cell records only (their runs, bricks "
        "and cones add a few percent).\n\n";
  if (!info.pipelineStatistics) md += "This device has no pipeline-statistics queries: those columns are empty.\n\n";
  paperTable(md, rows);
  targets(md, rows, info);
  countTargets(md, rows, info);
  objectsSection(md, rows, info);
  md += "## Charts\n\n";
  ENGINE_TRY(chartSection(md, folder, "time_vs_k.png", "GPU ms per frame vs K (log-log)",
                          chartOf(rows, [](const RowResult& r) { return glm::dvec2(r.spec.resolution, r.gpuMsMedian); },
                                  false)));
  Chart errorVsBytes = chartOf(
      rows, [](const RowResult& r) { return glm::dvec2(double(r.storedBytes), r.quality.normalErrorMean); }, false);
  errorVsBytes.decimalX = true;
  ENGINE_TRY(chartSection(md, folder, "normal_error_vs_bytes.png", "Mean normal error (deg) vs stored bytes (log-log)",
                          errorVsBytes));
  ENGINE_TRY(chartSection(md, folder, "work_vs_k.png", "Root-search evaluations per covered pixel vs K (log-log)",
                          chartOf(rows, [](const RowResult& r) { return glm::dvec2(r.spec.resolution, r.quality.evalsMean); },
                                  false)));
  if (info.pipelineStatistics)
    ENGINE_TRY(chartSection(
        md, folder, "fragments_vs_k.png", "Prepass fragment-shader invocations per covered pixel vs K (log-log)",
        chartOf(rows,
                [&](const RowResult& r) {
                  return glm::dvec2(r.spec.resolution, perCovered(r.prepassFsInvocations, r, info.views));
                },
                false)));
  allRows(md, rows, info);
  passTable(md, rows);
  return engine::writeTextFile(folder / "results.md", md);
}

}  // namespace capture
