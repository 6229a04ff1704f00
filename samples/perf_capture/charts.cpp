#include "charts.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include <fmt/format.h>

#include "engine/core/image_io.h"

namespace capture {
namespace {

// 3x5 glyphs, one row of 3 bits per entry, top row first: 0-9, '.', '-', 'e', '+'.
constexpr std::uint8_t kGlyphs[14][5] = {
    {7, 5, 5, 5, 7}, {2, 6, 2, 2, 7}, {7, 1, 7, 4, 7}, {7, 1, 7, 1, 7}, {5, 5, 7, 1, 1}, {7, 4, 7, 1, 7},
    {7, 4, 7, 5, 7}, {7, 1, 1, 1, 1}, {7, 5, 7, 5, 7}, {7, 5, 7, 1, 7}, {0, 0, 0, 0, 2}, {0, 0, 7, 0, 0},
    {0, 7, 5, 6, 7}, {0, 2, 7, 2, 0}};

class Canvas {
 public:
  Canvas(int width, int height) : width_(width), height_(height), pixels_(std::size_t(width * height) * 3, 255) {}

  void set(int x, int y, glm::u8vec3 c) {
    if (x < 0 || y < 0 || x >= width_ || y >= height_) return;
    std::uint8_t* p = &pixels_[(std::size_t(y) * std::size_t(width_) + std::size_t(x)) * 3];
    p[0] = c.r, p[1] = c.g, p[2] = c.b;
  }
  void fill(int x0, int y0, int x1, int y1, glm::u8vec3 c) {
    for (int y = y0; y <= y1; ++y)
      for (int x = x0; x <= x1; ++x) set(x, y, c);
  }
  // A line `thickness` pixels wide (a square brush along the DDA).
  void line(glm::dvec2 a, glm::dvec2 b, glm::u8vec3 c, int thickness) {
    const int steps = std::max(1, int(std::ceil(std::max(std::abs(b.x - a.x), std::abs(b.y - a.y)))));
    for (int i = 0; i <= steps; ++i) {
      const glm::dvec2 p = a + (b - a) * (double(i) / steps);
      fill(int(p.x) - thickness / 2, int(p.y) - thickness / 2, int(p.x) + thickness / 2, int(p.y) + thickness / 2, c);
    }
  }
  // Text of digits, '.', '-', 'e' at scale 2; other characters leave a gap.
  void text(int x, int y, const std::string& s, glm::u8vec3 c) {
    for (char ch : s) {
      int g = -1;
      if (ch >= '0' && ch <= '9') g = ch - '0';
      if (ch == '.') g = 10;
      if (ch == '-') g = 11;
      if (ch == 'e') g = 12;
      if (ch == '+') g = 13;
      for (int row = 0; g >= 0 && row < 5; ++row)
        for (int col = 0; col < 3; ++col)
          if (kGlyphs[g][row] & (4 >> col)) fill(x + col * 2, y + row * 2, x + col * 2 + 1, y + row * 2 + 1, c);
      x += 8;
    }
  }
  const std::vector<std::uint8_t>& pixels() const { return pixels_; }

 private:
  int width_, height_;
  std::vector<std::uint8_t> pixels_;
};

struct Axis {
  double lo = 0.0, hi = 1.0;
  bool log = false;
  double map(double v) const {  // 0..1
    const double a = log ? std::log(lo) : lo, b = log ? std::log(hi) : hi, x = log ? std::log(v) : v;
    return b > a ? (x - a) / (b - a) : 0.5;
  }
};

Axis fitAxis(const Chart& chart, bool x, bool log) {
  Axis axis;
  axis.log = log;
  double lo = std::numeric_limits<double>::infinity(), hi = -lo;
  for (const ChartSeries& s : chart.series)
    for (const glm::dvec2& p : s.points) {
      const double v = x ? p.x : p.y;
      if (!std::isfinite(v) || (log && v <= 0.0)) continue;
      lo = std::min(lo, v), hi = std::max(hi, v);
    }
  if (!(lo <= hi)) lo = 1.0, hi = 10.0;
  if (log) {
    axis.lo = lo / 1.25, axis.hi = hi * 1.25;
  } else {
    const double pad = hi > lo ? 0.08 * (hi - lo) : 0.5;
    axis.lo = std::min(0.0, lo - pad), axis.hi = hi + pad;
  }
  return axis;
}

// Tick values: powers of two (log x), 1-2-5 per decade (log y), or ten steps (linear).
std::vector<double> ticks(const Axis& axis, bool base2) {
  std::vector<double> values;
  if (axis.log && base2) {
    for (double v = std::exp2(std::floor(std::log2(axis.lo))); v <= axis.hi; v *= 2.0)
      if (v >= axis.lo) values.push_back(v);
  } else if (axis.log) {
    for (double d = std::pow(10.0, std::floor(std::log10(axis.lo))); d <= axis.hi; d *= 10.0)
      for (double m : {1.0, 2.0, 5.0})
        if (m * d >= axis.lo && m * d <= axis.hi) values.push_back(m * d);
  } else {
    const double step = (axis.hi - axis.lo) / 10.0;
    for (int i = 0; i <= 10; ++i) values.push_back(axis.lo + step * i);
  }
  return values;
}

std::string tickLabel(double v) {
  if (v != 0.0 && (std::abs(v) >= 1e5 || std::abs(v) < 1e-2)) return fmt::format("{:.1e}", v);
  return fmt::format("{:g}", std::round(v * 1000.0) / 1000.0);
}

}  // namespace

glm::u8vec3 seriesColor(std::size_t index) {
  static const glm::u8vec3 palette[] = {{31, 119, 180}, {255, 127, 14}, {44, 160, 44},  {214, 39, 40},
                                        {148, 103, 189}, {140, 86, 75},  {227, 119, 194}, {127, 127, 127},
                                        {188, 189, 34},  {23, 190, 207}, {0, 0, 0},       {255, 200, 0}};
  return palette[index % std::size(palette)];
}

std::string colorHex(glm::u8vec3 c) { return fmt::format("#{:02x}{:02x}{:02x}", c.r, c.g, c.b); }

engine::Status writeChart(const std::filesystem::path& path, const Chart& chart, int width, int height) {
  Canvas canvas(width, height);
  const int left = 90, right = width - 20, top = 20, bottom = height - 40;
  const Axis ax = fitAxis(chart, true, chart.logX), ay = fitAxis(chart, false, chart.logY);
  auto toPixel = [&](glm::dvec2 p) {
    return glm::dvec2(left + ax.map(p.x) * (right - left), bottom - ay.map(p.y) * (bottom - top));
  };
  const glm::u8vec3 grid{225, 225, 225}, ink{40, 40, 40};
  for (double v : ticks(ax, !chart.decimalX)) {
    const double x = toPixel({v, ay.lo}).x;
    canvas.line({x, double(top)}, {x, double(bottom)}, grid, 1);
    canvas.text(int(x) - 8, bottom + 8, tickLabel(v), ink);
  }
  for (double v : ticks(ay, false)) {
    const double y = toPixel({ax.lo, v}).y;
    canvas.line({double(left), y}, {double(right), y}, grid, 1);
    const std::string label = tickLabel(v);
    canvas.text(left - 8 - 8 * int(label.size()), int(y) - 5, label, ink);
  }
  canvas.line({double(left), double(bottom)}, {double(right), double(bottom)}, ink, 2);
  canvas.line({double(left), double(top)}, {double(left), double(bottom)}, ink, 2);
  for (std::size_t s = 0; s < chart.series.size(); ++s) {
    const ChartSeries& series = chart.series[s];
    bool havePrevious = false;
    glm::dvec2 previous{};
    for (const glm::dvec2& p : series.points) {
      if (!std::isfinite(p.x) || !std::isfinite(p.y) || (chart.logX && p.x <= 0) || (chart.logY && p.y <= 0)) continue;
      const glm::dvec2 q = toPixel(p);
      if (havePrevious) canvas.line(previous, q, series.color, 2);
      canvas.fill(int(q.x) - 3, int(q.y) - 3, int(q.x) + 3, int(q.y) + 3, series.color);
      previous = q, havePrevious = true;
    }
    // Legend: one square per series, in order, so results.md can name them.
    const int lx = left + 12 + int(s) * 22, ly = top + 8;
    canvas.fill(lx, ly, lx + 14, ly + 14, series.color);
  }
  return engine::writePng(path, canvas.pixels(), std::uint32_t(width), std::uint32_t(height), 3);
}

}  // namespace capture
