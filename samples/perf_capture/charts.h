#pragma once
// Simple line charts as PNG (engine/core/image_io.h), drawn by a tiny rasterizer: axes with tick
// values (a 3x5 pixel digit font), one polyline with dot markers per series and a legend of
// coloured squares in the top-left corner, in series order. The series names go beside the chart
// (results.md lists them with their colours): the font has digits only.
#include <filesystem>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "engine/core/expected.h"

namespace capture {

struct ChartSeries {
  std::string name;
  glm::u8vec3 color;
  std::vector<glm::dvec2> points;  // drawn in the order given; non-positive values on a log axis are skipped
};

struct Chart {
  bool logX = true;  // base-2 ticks (K), or 1-2-5 per decade with decimalX (bytes)
  bool decimalX = false;
  bool logY = true;  // base-10 ticks (1, 2, 5 per decade)
  std::vector<ChartSeries> series;
};

// A distinct colour per index (a fixed palette, then repeated).
glm::u8vec3 seriesColor(std::size_t index);
std::string colorHex(glm::u8vec3 color);

engine::Status writeChart(const std::filesystem::path& path, const Chart& chart, int width = 800, int height = 500);

}  // namespace capture
