// curve2d: the paper's 2D figure. The curve f(x,y) = (x^2+y^2)^2 - 2(y^2-x^2) - 0.1255 = 0 (a
// peanut with a narrow waist) sampled on a coarse K x K grid of values and gradients, then
// reconstructed with bilinear interpolation of the values and with bicubic (Ferguson, zero twist)
// Hermite interpolation of values and gradients -- the 2D case of the module's tricubic cells,
// through the same basis functions (hermite_sdf/core/hermite.h). One PNG, left to right: the exact
// curve, bilinear, Hermite; the exact curve is drawn in red over both reconstructions, grid
// samples as dots. It also prints how far each reconstructed curve is from the exact one.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>
#include <glm/glm.hpp>

#include "engine/core/image_io.h"
#include "hermite_sdf/core/hermite.h"

namespace {

constexpr double kExtent = 1.6;  // the domain is [-kExtent, kExtent]^2

double exactValue(double x, double y) {
  const double r2 = x * x + y * y;
  return r2 * r2 - 2.0 * (y * y - x * x) - 0.1255;
}

glm::dvec2 exactGradient(double x, double y) {
  const double r2 = x * x + y * y;
  return {4.0 * r2 * x + 4.0 * x, 4.0 * r2 * y - 4.0 * y};
}

using Field2D = std::function<double(double, double)>;

// The exact function sampled at the K x K grid nodes: values and world-space gradients.
struct Grid2D {
  int k = 0;
  double h = 0.0;
  std::vector<double> f, fx, fy;  // index i + k j

  explicit Grid2D(int resolution) : k(resolution), h(2.0 * kExtent / (resolution - 1)) {
    for (int j = 0; j < k; ++j)
      for (int i = 0; i < k; ++i) {
        const glm::dvec2 p = node(i, j);
        const glm::dvec2 g = exactGradient(p.x, p.y);
        f.push_back(exactValue(p.x, p.y));
        fx.push_back(g.x);
        fy.push_back(g.y);
      }
  }
  glm::dvec2 node(int i, int j) const { return {-kExtent + i * h, -kExtent + j * h}; }

  // The cell holding (x, y) and the local coordinates in it.
  void locate(double x, double y, int& i, int& j, double& u, double& v) const {
    const double gx = std::clamp((x + kExtent) / h, 0.0, double(k - 1));
    const double gy = std::clamp((y + kExtent) / h, 0.0, double(k - 1));
    i = std::min(int(gx), k - 2);
    j = std::min(int(gy), k - 2);
    u = gx - i;
    v = gy - j;
  }

  double bilinear(double x, double y) const {
    int i, j;
    double u, v;
    locate(x, y, i, j, u, v);
    const auto at = [&](int di, int dj) { return f[std::size_t(i + di + k * (j + dj))]; };
    return (1 - v) * ((1 - u) * at(0, 0) + u * at(1, 0)) + v * ((1 - u) * at(0, 1) + u * at(1, 1));
  }

  // F(u,v) = sum_c f_c Hx Hy + h (fx_c Gx Hy + fy_c Hx Gy): hermite.h's tricubic with z dropped.
  double hermite(double x, double y) const {
    int i, j;
    double u, v;
    locate(x, y, i, j, u, v);
    const hsdf::HermiteBasis1D<double> bu = hsdf::hermiteBasis(u), bv = hsdf::hermiteBasis(v);
    double value = 0.0;
    for (int dj = 0; dj < 2; ++dj)
      for (int di = 0; di < 2; ++di) {
        const std::size_t c = std::size_t(i + di + k * (j + dj));
        value += f[c] * bu.value(di) * bv.value(dj) +
                 h * (fx[c] * bu.slope(di) * bv.value(dj) + fy[c] * bu.value(di) * bv.slope(dj));
      }
    return value;
  }
};

// How far one zero set is from another, both ways, estimated to first order as |g| / |grad g| at
// the zero crossings of the other function on a fine raster (crossings located by linear
// interpolation along raster edges).
struct CurveDistance {
  double mean = 0.0;
  double max = 0.0;
  std::size_t points = 0;
};

glm::dvec2 numericGradient(const Field2D& g, double x, double y, double step) {
  return {(g(x + step, y) - g(x - step, y)) / (2 * step), (g(x, y + step) - g(x, y - step)) / (2 * step)};
}

void accumulateOneWay(const Field2D& from, const Field2D& to, int raster, CurveDistance& d, double& sum) {
  const double step = 2.0 * kExtent / raster;
  auto coord = [&](int n) { return -kExtent + (n + 0.5) * step; };
  auto measure = [&](double x, double y) {
    const glm::dvec2 g = numericGradient(to, x, y, 1e-6);
    const double distance = std::abs(to(x, y)) / std::max(glm::length(g), 1e-12);
    sum += distance;
    d.max = std::max(d.max, distance);
    ++d.points;
  };
  for (int j = 0; j < raster; ++j)
    for (int i = 0; i < raster; ++i) {
      const double x = coord(i), y = coord(j), a = from(x, y);
      if (i + 1 < raster) {
        const double b = from(coord(i + 1), y);
        if ((a < 0) != (b < 0)) measure(x + step * a / (a - b), y);
      }
      if (j + 1 < raster) {
        const double b = from(x, coord(j + 1));
        if ((a < 0) != (b < 0)) measure(x, y + step * a / (a - b));
      }
    }
}

CurveDistance curveDistance(const Field2D& reconstructed, const Field2D& exact, int raster) {
  CurveDistance d;
  double sum = 0.0;
  accumulateOneWay(reconstructed, exact, raster, d, sum);  // points of the reconstruction off the curve
  accumulateOneWay(exact, reconstructed, raster, d, sum);  // pieces of the curve the reconstruction misses
  d.mean = d.points ? sum / double(d.points) : 0.0;
  return d;
}

// One panel: inside tinted, the field's zero set black, optionally the exact curve in red and the
// grid nodes as dots.
struct Canvas {
  int width, height;
  std::vector<std::uint8_t> rgb;
  Canvas(int w, int h) : width(w), height(h), rgb(std::size_t(w) * h * 3, 255) {}
  void set(int x, int y, std::uint8_t r, std::uint8_t g, std::uint8_t b) {
    if (x < 0 || y < 0 || x >= width || y >= height) return;
    std::uint8_t* p = &rgb[3 * (std::size_t(y) * width + x)];
    p[0] = r;
    p[1] = g;
    p[2] = b;
  }
};

void drawPanel(Canvas& canvas, int left, int size, const Field2D& field, const Grid2D* grid) {
  auto world = [&](int p) { return -kExtent + (p + 0.5) * 2.0 * kExtent / size; };
  std::vector<double> values(std::size_t(size) * size), exact(values.size());
  for (int y = 0; y < size; ++y)
    for (int x = 0; x < size; ++x) {
      values[std::size_t(y) * size + x] = field(world(x), -world(y));  // image rows go down
      exact[std::size_t(y) * size + x] = exactValue(world(x), -world(y));
    }
  auto crosses = [&](const std::vector<double>& v, int x, int y) {
    const bool in = v[std::size_t(y) * size + x] < 0;
    return (x + 1 < size && (v[std::size_t(y) * size + x + 1] < 0) != in) ||
           (y + 1 < size && (v[std::size_t(y + 1) * size + x] < 0) != in);
  };
  for (int y = 0; y < size; ++y)
    for (int x = 0; x < size; ++x) {
      if (values[std::size_t(y) * size + x] < 0) canvas.set(left + x, y, 205, 222, 245);
      if (grid && crosses(exact, x, y)) canvas.set(left + x, y, 230, 40, 40);
    }
  for (int y = 0; y < size; ++y)
    for (int x = 0; x < size; ++x)
      if (crosses(values, x, y))
        for (int d = 0; d < 2; ++d) canvas.set(left + x + d, y, 0, 0, 0), canvas.set(left + x, y + d, 0, 0, 0);
  if (!grid) return;
  for (int j = 0; j < grid->k; ++j)
    for (int i = 0; i < grid->k; ++i) {
      const glm::dvec2 p = grid->node(i, j);
      const int px = int((p.x + kExtent) / (2 * kExtent) * size), py = int((kExtent - p.y) / (2 * kExtent) * size);
      for (int dy = -2; dy <= 2; ++dy)
        for (int dx = -2; dx <= 2; ++dx) canvas.set(left + px + dx, py + dy, 60, 90, 200);
    }
}

}  // namespace

int main(int argc, char** argv) {
  std::string output = "curve2d.png";
  int resolution = 8;
  int size = 360;
  CLI::App app{"curve2d: the paper's 2D curve from a coarse grid, bilinear vs bicubic Hermite, as one PNG", "curve2d"};
  app.add_option("-o,--output", output, "PNG to write (default curve2d.png)");
  app.add_option("-k,--grid", resolution, "grid samples per axis K (3..64, default 8)")->check(CLI::Range(3, 64));
  app.add_option("--size", size, "pixels per panel side (64..2048, default 360)")->check(CLI::Range(64, 2048));
  CLI11_PARSE(app, argc, argv);

  const Grid2D grid(resolution);
  const Field2D exact = exactValue;
  const Field2D bilinear = [&grid](double x, double y) { return grid.bilinear(x, y); };
  const Field2D hermite = [&grid](double x, double y) { return grid.hermite(x, y); };

  const int gap = 8;
  Canvas canvas(3 * size + 2 * gap, size);
  for (int y = 0; y < size; ++y)
    for (int x = 0; x < gap; ++x) canvas.set(size + x, y, 128, 128, 128), canvas.set(2 * size + gap + x, y, 128, 128, 128);
  drawPanel(canvas, 0, size, exact, nullptr);
  drawPanel(canvas, size + gap, size, bilinear, &grid);
  drawPanel(canvas, 2 * (size + gap), size, hermite, &grid);
  if (auto written = engine::writePng(output, canvas.rgb, std::uint32_t(canvas.width), std::uint32_t(canvas.height), 3);
      !written) {
    std::fprintf(stderr, "curve2d: %s\n", written.error().message.c_str());
    return 1;
  }

  std::printf("grid %dx%d, spacing h = %.4f over [-%.1f, %.1f]^2; wrote %s (%dx%d: exact | bilinear | Hermite)\n",
              resolution, resolution, grid.h, kExtent, kExtent, output.c_str(), canvas.width, canvas.height);
  std::printf("distance to the exact curve (both ways, 1024^2 raster, world units):\n");
  const struct {
    const char* name;
    const Field2D* field;
  } rows[] = {{"exact", &exact}, {"bilinear", &bilinear}, {"hermite", &hermite}};
  for (const auto& row : rows) {
    const CurveDistance d = curveDistance(*row.field, exact, 1024);
    std::printf("%-8s mean %.6f max %.6f (%zu points)\n", row.name, d.mean, d.max, d.points);
  }
  return 0;
}
