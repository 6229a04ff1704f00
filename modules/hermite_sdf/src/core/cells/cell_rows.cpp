#include "cells/cell_rows.h"

#include <algorithm>
#include <cmath>

namespace hsdf {
namespace {

// Records gone through by calls made on this thread (cellRowsAndRunsBuiltOnThisThread).
thread_local std::uint64_t recordsBuiltHere = 0;

// Squared distance from a point to the unit box of cell c.
double distanceToCellSquared(const glm::dvec3& p, const glm::dvec3& c) {
  const glm::dvec3 d = glm::max(glm::max(c - p, p - (c + 1.0)), glm::dvec3(0.0));
  return glm::dot(d, d);
}

}  // namespace

CellRows buildCellRows(const CellStream& stream) {
  CellRows result;
  recordsBuiltHere += stream.records.size();
  result.recordCount = static_cast<std::uint32_t>(stream.records.size());
  result.recordOfCell.reserve(stream.records.size());
  for (std::uint32_t i = 0; i < stream.records.size(); ++i) {
    const CellRecord& r = stream.records[i];
    result.recordOfCell.emplace_back(CellRows::cellKey(r.x, r.y, r.z), i);
    if (result.rows.empty() || result.rows.back().y != r.y || result.rows.back().z != r.z) {
      if (result.rows.empty() || result.rows.back().z != r.z)
        result.zGroups.push_back(static_cast<std::uint32_t>(result.rows.size()));
      result.rows.push_back({i, 0, r.y, r.z});
    }
    result.rows.back().count++;
  }
  result.zGroups.push_back(static_cast<std::uint32_t>(result.rows.size()));
  auto& keys = result.recordOfCell;
  if (!std::is_sorted(keys.begin(), keys.end())) std::sort(keys.begin(), keys.end());
  return result;
}

std::optional<std::uint32_t> CellRows::recordOf(std::uint32_t x, std::uint32_t y, std::uint32_t z) const {
  const std::uint64_t key = cellKey(x, y, z);
  const auto it = std::lower_bound(recordOfCell.begin(), recordOfCell.end(), key,
                                   [](const auto& entry, std::uint64_t k) { return entry.first < k; });
  if (it == recordOfCell.end() || it->first != key) return std::nullopt;
  return it->second;
}

std::vector<CellRows::Range> orderedRows(const CellRows& rows, const glm::dvec3& eyeGrid, bool frontToBack) {
  std::vector<CellRows::Range> ranges;
  if (rows.recordCount == 0) return ranges;
  if (!frontToBack) {
    ranges.push_back({0, rows.recordCount});
    return ranges;
  }
  // Groups of equal z nearest to the eye first; within a group, rows of nearest y first.
  const std::size_t groupCount = rows.zGroups.size() - 1;
  std::vector<std::uint32_t> groups(groupCount);
  for (std::uint32_t g = 0; g < groupCount; ++g) groups[g] = g;
  auto zDistance = [&](std::uint32_t g) { return std::abs(double(rows.rows[rows.zGroups[g]].z) + 0.5 - eyeGrid.z); };
  std::stable_sort(groups.begin(), groups.end(), [&](auto a, auto b) { return zDistance(a) < zDistance(b); });

  std::vector<std::uint32_t> order;
  for (std::uint32_t g : groups) {
    order.clear();
    for (std::uint32_t r = rows.zGroups[g]; r < rows.zGroups[g + 1]; ++r) order.push_back(r);
    auto yDistance = [&](std::uint32_t r) { return std::abs(double(rows.rows[r].y) + 0.5 - eyeGrid.y); };
    std::stable_sort(order.begin(), order.end(), [&](auto a, auto b) { return yDistance(a) < yDistance(b); });
    for (std::uint32_t r : order) {
      const CellRows::Row& row = rows.rows[r];
      if (!ranges.empty() && ranges.back().first + ranges.back().count == row.first)
        ranges.back().count += row.count;
      else
        ranges.push_back({row.first, row.count});
    }
  }
  return ranges;
}

std::vector<std::uint32_t> cellsNearPoint(const CellRows& rows, const CellStream& stream, const glm::dvec3& point,
                                          double radius) {
  std::vector<std::uint32_t> result;
  const int cellsPerAxis = stream.grid.cellsPerAxis();
  if (cellsPerAxis <= 0 || !std::isfinite(radius) || radius < 0.0) return result;
  const glm::dvec3 lo = glm::floor(point - radius), hi = glm::floor(point + radius);
  const glm::ivec3 first = glm::clamp(glm::ivec3(glm::max(lo, glm::dvec3(-1.0))), 0, cellsPerAxis - 1);
  const glm::ivec3 last = glm::clamp(glm::ivec3(glm::min(hi, glm::dvec3(cellsPerAxis))), 0, cellsPerAxis - 1);
  if (glm::any(glm::lessThan(hi, glm::dvec3(0.0))) || glm::any(glm::greaterThan(lo, glm::dvec3(cellsPerAxis - 1))))
    return result;
  const double r2 = radius * radius;
  const glm::dvec3 span = glm::dvec3(last - first) + 1.0;
  if (span.x * span.y * span.z > double(stream.records.size())) {
    // The neighbourhood holds more cells than the stream: scan the records instead.
    for (std::uint32_t i = 0; i < stream.records.size(); ++i) {
      const CellRecord& r = stream.records[i];
      if (distanceToCellSquared(point, glm::dvec3(r.x, r.y, r.z)) <= r2) result.push_back(i);
    }
    return result;
  }
  for (int z = first.z; z <= last.z; ++z)
    for (int y = first.y; y <= last.y; ++y)
      for (int x = first.x; x <= last.x; ++x) {
        if (distanceToCellSquared(point, glm::dvec3(x, y, z)) > r2) continue;
        if (const auto record = rows.recordOf(std::uint32_t(x), std::uint32_t(y), std::uint32_t(z)))
          result.push_back(*record);
      }
  return result;
}

std::vector<shader::CellRunGpu> buildCellRuns(const CellStream& stream, std::uint32_t maxLength) {
  std::vector<shader::CellRunGpu> runs;
  recordsBuiltHere += stream.records.size();
  maxLength = std::clamp(maxLength, 1u, 0xffffu);
  std::uint32_t length = 0;
  for (std::uint32_t i = 0; i < stream.records.size(); ++i) {
    const CellRecord& r = stream.records[i];
    const bool extends = length > 0 && length < maxLength && stream.records[i - 1].y == r.y &&
                         stream.records[i - 1].z == r.z && stream.records[i - 1].x + 1u == r.x;
    if (extends) {
      ++length;
    } else {
      if (length > 0) runs.back().zLength = (runs.back().zLength & 0xffffu) | (length << 16);
      runs.push_back({std::uint32_t(r.x) | (std::uint32_t(r.y) << 16), std::uint32_t(r.z), i});
      length = 1;
    }
  }
  if (length > 0) runs.back().zLength = (runs.back().zLength & 0xffffu) | (length << 16);
  return runs;
}

std::uint64_t cellRowsAndRunsBuiltOnThisThread() { return recordsBuiltHere; }

std::vector<CellRows::Range> runRanges(const std::vector<shader::CellRunGpu>& runs,
                                       const std::vector<CellRows::Range>& recordRanges) {
  std::vector<CellRows::Range> result;
  auto runAt = [&](std::uint32_t record) {  // the first run whose first record is >= record
    auto it = std::lower_bound(runs.begin(), runs.end(), record,
                               [](const shader::CellRunGpu& run, std::uint32_t r) { return run.firstRecord < r; });
    return static_cast<std::uint32_t>(it - runs.begin());
  };
  for (const CellRows::Range& range : recordRanges) {
    const std::uint32_t first = runAt(range.first), end = runAt(range.first + range.count);
    if (end <= first) continue;
    if (!result.empty() && result.back().first + result.back().count == first)
      result.back().count += end - first;
    else
      result.push_back({first, end - first});
  }
  return result;
}

std::vector<std::uint32_t> runsNearPoint(const std::vector<shader::CellRunGpu>& runs, const glm::dvec3& point,
                                         double radius) {
  std::vector<std::uint32_t> result;
  if (!std::isfinite(radius) || radius < 0.0) return result;
  const double r2 = radius * radius;
  for (std::uint32_t i = 0; i < runs.size(); ++i) {
    const shader::CellRunGpu& run = runs[i];
    const glm::dvec3 lo(run.xy & 0xffffu, run.xy >> 16, run.zLength & 0xffffu);
    const glm::dvec3 hi = lo + glm::dvec3(double(run.zLength >> 16), 1.0, 1.0);
    const glm::dvec3 d = glm::max(glm::max(lo - point, point - hi), glm::dvec3(0.0));
    if (glm::dot(d, d) <= r2) result.push_back(i);
  }
  return result;
}

}  // namespace hsdf
