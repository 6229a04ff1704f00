#include "ground_truth.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <limits>
#include <thread>

namespace capture {
namespace {

using engine::math::Ray;
constexpr double kInfinity = std::numeric_limits<double>::infinity();

// Entry and exit of the ray through the box, or an empty interval (x > y).
glm::dvec2 slabs(const Ray& ray, const glm::dvec3& lo, const glm::dvec3& hi) {
  double t0 = 0.0, t1 = kInfinity;
  for (int a = 0; a < 3; ++a) {
    const double inv = 1.0 / ray.direction[a];
    double n = (lo[a] - ray.origin[a]) * inv, f = (hi[a] - ray.origin[a]) * inv;
    if (n > f) std::swap(n, f);
    if (std::isnan(n) || std::isnan(f)) {  // parallel to the slab: inside it or not
      if (ray.origin[a] < lo[a] || ray.origin[a] > hi[a]) return {1.0, 0.0};
      continue;
    }
    t0 = std::max(t0, n);
    t1 = std::min(t1, f);
  }
  return {t0, t1};
}

class MeshSurface final : public TruthSurface {
 public:
  explicit MeshSurface(const engine::scene::TriangleSoup& soup) {
    const bool parts = soup.triangleNodes.size() * 3 == soup.indices.size();
    for (std::size_t i = 0; i + 2 < soup.indices.size(); i += 3) {
      Triangle t;
      t.part = parts ? std::int32_t(soup.triangleNodes[i / 3]) : -1;
      for (int k = 0; k < 3; ++k) t.p[k] = glm::dvec3(soup.positions[soup.indices[i + std::size_t(k)]]);
      const glm::dvec3 n = glm::cross(t.p[1] - t.p[0], t.p[2] - t.p[0]);
      if (glm::length(n) == 0.0) continue;  // no area, no hit
      t.normal = glm::normalize(n);
      triangles_.push_back(t);
    }
    std::vector<std::uint32_t> order(triangles_.size());
    for (std::uint32_t i = 0; i < order.size(); ++i) order[i] = i;
    if (!order.empty()) build(order, 0, std::uint32_t(order.size()));
    std::vector<Triangle> sorted;
    for (std::uint32_t i : order) sorted.push_back(triangles_[i]);
    triangles_ = std::move(sorted);
  }

  std::optional<TruthHit> cast(const Ray& ray) const override {
    if (nodes_.empty()) return std::nullopt;
    double best = kInfinity;
    const Triangle* hit = nullptr;
    std::uint32_t stack[64];
    int top = 0;
    stack[top++] = 0;
    while (top > 0) {
      const Node& node = nodes_[stack[--top]];
      const glm::dvec2 span = slabs(ray, node.lo, node.hi);
      if (span.x > span.y || span.x > best) continue;
      if (node.count > 0) {
        for (std::uint32_t i = node.first; i < node.first + node.count; ++i) {
          const double t = intersect(triangles_[i], ray);
          if (t < best) best = t, hit = &triangles_[i];
        }
        continue;
      }
      if (top + 2 > 64) continue;  // cannot happen with median splits of < 2^60 triangles
      stack[top++] = node.first;  // right child
      stack[top++] = node.index + 1;  // left child, visited first
    }
    if (!hit) return std::nullopt;
    // The face normal facing the ray: the first hit from outside is on the outward side.
    const glm::dvec3 n = glm::dot(hit->normal, ray.direction) > 0.0 ? -hit->normal : hit->normal;
    return TruthHit{best, n, hit->part};
  }

 private:
  struct Triangle {
    glm::dvec3 p[3];
    glm::dvec3 normal;
    std::int32_t part = -1;
  };
  struct Node {
    glm::dvec3 lo, hi;
    std::uint32_t index = 0;  // own index (the left child is index + 1)
    std::uint32_t first = 0;  // leaf: first triangle; inner: right child
    std::uint32_t count = 0;  // leaf: triangles; inner: 0
  };

  // Möller–Trumbore; infinity on a miss.
  static double intersect(const Triangle& t, const Ray& ray) {
    const glm::dvec3 e1 = t.p[1] - t.p[0], e2 = t.p[2] - t.p[0];
    const glm::dvec3 q = glm::cross(ray.direction, e2);
    const double det = glm::dot(e1, q);
    if (det == 0.0) return kInfinity;
    const double inv = 1.0 / det;
    const glm::dvec3 s = ray.origin - t.p[0];
    const double u = glm::dot(s, q) * inv;
    if (u < 0.0 || u > 1.0) return kInfinity;
    const glm::dvec3 r = glm::cross(s, e1);
    const double v = glm::dot(ray.direction, r) * inv;
    if (v < 0.0 || u + v > 1.0) return kInfinity;
    const double d = glm::dot(e2, r) * inv;
    return d > 0.0 ? d : kInfinity;
  }

  std::uint32_t build(std::vector<std::uint32_t>& order, std::uint32_t begin, std::uint32_t end) {
    const auto index = std::uint32_t(nodes_.size());
    nodes_.push_back({});
    glm::dvec3 lo(kInfinity), hi(-kInfinity), clo(kInfinity), chi(-kInfinity);
    for (std::uint32_t i = begin; i < end; ++i) {
      const Triangle& t = triangles_[order[i]];
      for (const glm::dvec3& p : t.p) lo = glm::min(lo, p), hi = glm::max(hi, p);
      const glm::dvec3 c = (t.p[0] + t.p[1] + t.p[2]) / 3.0;
      clo = glm::min(clo, c), chi = glm::max(chi, c);
    }
    Node node{lo, hi, index, begin, end - begin};
    if (end - begin > 4) {
      const glm::dvec3 extent = chi - clo;
      const int axis = extent.x > extent.y ? (extent.x > extent.z ? 0 : 2) : (extent.y > extent.z ? 1 : 2);
      const std::uint32_t mid = begin + (end - begin) / 2;
      std::nth_element(order.begin() + begin, order.begin() + mid, order.begin() + end,
                       [&](std::uint32_t a, std::uint32_t b) {
                         const Triangle &ta = triangles_[a], &tb = triangles_[b];
                         return ta.p[0][axis] + ta.p[1][axis] + ta.p[2][axis] <
                                tb.p[0][axis] + tb.p[1][axis] + tb.p[2][axis];
                       });
      build(order, begin, mid);
      node.first = build(order, mid, end);
      node.count = 0;
    }
    nodes_[index] = node;
    return index;
  }

  std::vector<Triangle> triangles_;
  std::vector<Node> nodes_;
};

class AnalyticSurface final : public TruthSurface {
 public:
  explicit AnalyticSurface(std::unique_ptr<hsdf::SdfSource> source) : source_(std::move(source)) {
    const hsdf::Aabb b = source_->bounds();
    const glm::dvec3 margin(0.01 * glm::length(b.size()));
    lo_ = b.min - margin;
    hi_ = b.max + margin;
    tolerance_ = 1e-9 * glm::length(b.size());
  }

  std::optional<TruthHit> cast(const Ray& ray) const override {
    const glm::dvec2 span = slabs(ray, lo_, hi_);
    if (span.x > span.y) return std::nullopt;
    double t = span.x;
    for (int step = 0; step < 100000 && t <= span.y; ++step) {
      const hsdf::SdfSample s = source_->sample(ray.origin + t * ray.direction);
      // A ray that starts inside the shape hits where it leaves, as the GPU's root search and the
      // reference caster do (the first sign change), not at its start.
      if (std::abs(s.value) < tolerance_) return TruthHit{t, glm::normalize(s.gradient)};
      t += std::abs(s.value);  // an exact distance: the ball of this radius holds no surface
    }
    return std::nullopt;
  }

 private:
  std::unique_ptr<hsdf::SdfSource> source_;
  glm::dvec3 lo_, hi_;
  double tolerance_ = 0.0;
};

}  // namespace

std::unique_ptr<TruthSurface> meshSurface(const engine::scene::TriangleSoup& soup) {
  return std::make_unique<MeshSurface>(soup);
}

std::unique_ptr<TruthSurface> analyticSurface(std::unique_ptr<hsdf::SdfSource> source) {
  return std::make_unique<AnalyticSurface>(std::move(source));
}

TruthImage castTruth(const TruthSurface& surface, const engine::render::CameraView& camera, int width, int height) {
  TruthImage image;
  image.width = width;
  image.height = height;
  image.distance.assign(std::size_t(width) * std::size_t(height), -1.0f);
  image.normal.assign(image.distance.size(), glm::vec3(0.0f));
  image.part.assign(image.distance.size(), -1);
  std::atomic<int> nextRow{0};
  auto worker = [&] {
    for (int y = nextRow++; y < height; y = nextRow++) {
      for (int x = 0; x < width; ++x) {
        // From the pixel's point on the near plane, as the GPU draws nothing nearer; the distance
        // is still counted from the ray's origin (the eye, or the orthographic camera's plane).
        const glm::vec2 pixel{float(x) + 0.5f, float(y) + 0.5f};
        const Ray ray = engine::math::pixelRayFromNearPlane(camera.view, camera.proj, pixel, {width, height});
        const std::optional<TruthHit> hit = surface.cast(ray);
        if (!hit) continue;
        const glm::dvec3 origin = engine::math::pixelRay(camera.view, camera.proj, pixel, {width, height}).origin;
        const double nearDistance = glm::length(ray.origin - origin);
        const std::size_t i = std::size_t(y) * std::size_t(width) + std::size_t(x);
        image.distance[i] = float(nearDistance + hit->distance);
        image.normal[i] = glm::vec3(hit->normal);
        image.part[i] = hit->part;
      }
    }
  };
  const unsigned threads = std::max(1u, std::thread::hardware_concurrency());
  std::vector<std::thread> pool;
  for (unsigned i = 0; i < threads; ++i) pool.emplace_back(worker);
  for (std::thread& t : pool) t.join();
  return image;
}

}  // namespace capture
