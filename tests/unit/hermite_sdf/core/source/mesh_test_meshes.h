#pragma once
// Closed meshes built in code for the mesh-source tests, and an independent brute-force distance.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <map>
#include <utility>
#include <vector>

#include <glm/glm.hpp>

namespace hsdf::testing {

struct TestMesh {
  std::vector<glm::vec3> positions;
  std::vector<std::uint32_t> indices;
  std::size_t triangleCount() const { return indices.size() / 3; }
};

// Icosphere of the given radius, outward counter-clockwise triangles, shared vertices;
// 20 * 4^subdivisions triangles.
inline TestMesh icosphere(int subdivisions, float radius = 1.0f) {
  const float t = (1.0f + std::sqrt(5.0f)) / 2.0f;
  std::vector<glm::vec3> v = {{-1, t, 0}, {1, t, 0}, {-1, -t, 0}, {1, -t, 0}, {0, -1, t}, {0, 1, t},
                              {0, -1, -t}, {0, 1, -t}, {t, 0, -1}, {t, 0, 1}, {-t, 0, -1}, {-t, 0, 1}};
  for (auto& p : v) p = glm::normalize(p);
  std::vector<std::uint32_t> f = {0, 11, 5, 0, 5, 1, 0, 1, 7, 0, 7, 10, 0, 10, 11, 1, 5, 9, 5, 11, 4,
                                  11, 10, 2, 10, 7, 6, 7, 1, 8, 3, 9, 4, 3, 4, 2, 3, 2, 6, 3, 6, 8,
                                  3, 8, 9, 4, 9, 5, 2, 4, 11, 6, 2, 10, 8, 6, 7, 9, 8, 1};
  for (int s = 0; s < subdivisions; ++s) {
    std::map<std::pair<std::uint32_t, std::uint32_t>, std::uint32_t> midpoints;
    auto midpoint = [&](std::uint32_t a, std::uint32_t b) {
      const auto key = std::minmax(a, b);
      auto it = midpoints.find(key);
      if (it != midpoints.end()) return it->second;
      v.push_back(glm::normalize(v[a] + v[b]));
      return midpoints[key] = std::uint32_t(v.size() - 1);
    };
    std::vector<std::uint32_t> next;
    for (std::size_t i = 0; i < f.size(); i += 3) {
      const std::uint32_t a = f[i], b = f[i + 1], c = f[i + 2];
      const std::uint32_t ab = midpoint(a, b), bc = midpoint(b, c), ca = midpoint(c, a);
      next.insert(next.end(), {a, ab, ca, b, bc, ab, c, ca, bc, ab, bc, ca});
    }
    f = std::move(next);
  }
  for (auto& p : v) p *= radius;
  return {v, f};
}

// A non-convex closed "blob" (icosphere with radial bumps): concave regions and a medial axis
// away from the centre, like a scanned model.
inline TestMesh bumpySphere(int subdivisions) {
  TestMesh m = icosphere(subdivisions);
  for (auto& p : m.positions) {
    const float bump = 1.0f + 0.25f * std::sin(3.0f * p.x + 1.0f) * std::sin(4.0f * p.y) * std::cos(2.0f * p.z);
    p *= bump;
  }
  return m;
}

// Axis-aligned cube [-h, h]^3, each face split into n x n quads, outward counter-clockwise.
inline TestMesh cube(int n, float h = 1.0f) {
  TestMesh m;
  const glm::vec3 axes[3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  for (int axis = 0; axis < 3; ++axis) {
    for (float side : {-1.0f, 1.0f}) {
      const glm::vec3 normal = side * axes[axis];
      const glm::vec3 u = axes[(axis + 1) % 3];
      const glm::vec3 w = side > 0 ? axes[(axis + 2) % 3] : -axes[(axis + 2) % 3];
      const std::uint32_t base = std::uint32_t(m.positions.size());
      for (int j = 0; j <= n; ++j)
        for (int i = 0; i <= n; ++i)
          // (2i - n) / n is exactly antisymmetric in i, so corners shared by two faces get
          // bit-identical coordinates (and weld) whichever face computes them.
          m.positions.push_back(h * (normal + (float(2 * i - n) / float(n)) * u + (float(2 * j - n) / float(n)) * w));
      auto at = [&](int i, int j) { return base + std::uint32_t(j * (n + 1) + i); };
      for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i)
          m.indices.insert(m.indices.end(), {at(i, j), at(i + 1, j), at(i + 1, j + 1), at(i, j), at(i + 1, j + 1),
                                             at(i, j + 1)});
    }
  }
  return m;
}

inline TestMesh withoutTriangle(TestMesh m, std::size_t t) {
  m.indices.erase(m.indices.begin() + std::ptrdiff_t(3 * t), m.indices.begin() + std::ptrdiff_t(3 * t + 3));
  return m;
}

inline TestMesh withFlippedTriangle(TestMesh m, std::size_t t) {
  std::swap(m.indices[3 * t + 1], m.indices[3 * t + 2]);
  return m;
}

inline glm::dvec3 corner(const TestMesh& m, std::size_t t, int k) {
  return glm::dvec3(m.positions[m.indices[3 * t + std::size_t(k)]]);
}

inline glm::dvec3 centroid(const TestMesh& m, std::size_t t) {
  return (corner(m, t, 0) + corner(m, t, 1) + corner(m, t, 2)) / 3.0;
}

// Distance from p to segment [a, b].
inline double segmentDistance(const glm::dvec3& p, const glm::dvec3& a, const glm::dvec3& b) {
  const glm::dvec3 ab = b - a;
  const double s = std::clamp(glm::dot(p - a, ab) / glm::dot(ab, ab), 0.0, 1.0);
  return glm::length(p - (a + s * ab));
}

// Distance to a triangle computed differently from the source (plane projection + barycentric
// inside test, else the nearest edge), so a shared bug cannot hide.
inline double triangleDistance(const glm::dvec3& p, const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c) {
  const glm::dvec3 n = glm::normalize(glm::cross(b - a, c - a));
  const glm::dvec3 q = p - glm::dot(p - a, n) * n;
  const bool inside = glm::dot(glm::cross(b - a, q - a), n) >= 0 && glm::dot(glm::cross(c - b, q - b), n) >= 0 &&
                      glm::dot(glm::cross(a - c, q - c), n) >= 0;
  if (inside) return std::abs(glm::dot(p - a, n));
  return std::min({segmentDistance(p, a, b), segmentDistance(p, b, c), segmentDistance(p, c, a)});
}

inline double bruteForceDistance(const TestMesh& m, const glm::dvec3& p) {
  double best = std::numeric_limits<double>::infinity();
  for (std::size_t t = 0; t < m.triangleCount(); ++t)
    best = std::min(best, triangleDistance(p, corner(m, t, 0), corner(m, t, 1), corner(m, t, 2)));
  return best;
}

}  // namespace hsdf::testing
