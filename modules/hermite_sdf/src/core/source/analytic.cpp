#include "hermite_sdf/core/analytic.h"

#include <algorithm>
#include <cmath>
#include <functional>
#include <map>

#include <fmt/format.h>

namespace hsdf {
namespace {

// Unit vector along v, or `fallback` where v has no direction.
glm::dvec3 directionOr(const glm::dvec3& v, const glm::dvec3& fallback) {
  const double len = glm::length(v);
  return len > 0.0 ? v / len : fallback;
}

double signNonNegative(double x) { return x < 0.0 ? -1.0 : 1.0; }

}  // namespace

SdfSample SphereSource::sample(const glm::dvec3& p) const {
  const glm::dvec3 d = p - center_;
  return {glm::length(d) - radius_, directionOr(d, {0.0, 0.0, 1.0})};
}

Aabb SphereSource::bounds() const { return {center_ - radius_, center_ + radius_}; }

SdfSample BoxSource::sample(const glm::dvec3& p) const {
  const glm::dvec3 local = p - center_;
  const glm::dvec3 sign(signNonNegative(local.x), signNonNegative(local.y), signNonNegative(local.z));
  const glm::dvec3 q = glm::abs(local) - half_;
  const glm::dvec3 outside = glm::max(q, glm::dvec3(0.0));
  const double outsideLength = glm::length(outside);
  if (outsideLength > 0.0) return {outsideLength, sign * outside / outsideLength};
  // Inside (or on the surface): distance to the nearest face, whose normal is the gradient.
  int axis = 0;
  if (q.y > q[axis]) axis = 1;
  if (q.z > q[axis]) axis = 2;
  glm::dvec3 gradient(0.0);
  gradient[axis] = sign[axis];
  return {q[axis], gradient};
}

Aabb BoxSource::bounds() const { return {center_ - half_, center_ + half_}; }

SdfSample TorusSource::sample(const glm::dvec3& p) const {
  const glm::dvec3 local = p - center_;
  const glm::dvec3 radial = directionOr({local.x, 0.0, local.z}, {1.0, 0.0, 0.0});
  const glm::dvec3 core = major_ * radial;  // nearest point of the core circle
  const glm::dvec3 toP = local - core;
  return {glm::length(toP) - minor_, directionOr(toP, {0.0, 1.0, 0.0})};
}

Aabb TorusSource::bounds() const {
  const glm::dvec3 extent(major_ + minor_, minor_, major_ + minor_);
  return {center_ - extent, center_ + extent};
}

SdfSample CapsuleSource::sample(const glm::dvec3& p) const {
  const glm::dvec3 ab = b_ - a_;
  const double lengthSquared = glm::dot(ab, ab);
  const double t = lengthSquared > 0.0 ? std::clamp(glm::dot(p - a_, ab) / lengthSquared, 0.0, 1.0) : 0.0;
  const glm::dvec3 toP = p - (a_ + t * ab);
  // A deterministic perpendicular of the axis for points on the segment itself.
  const glm::dvec3 axis = directionOr(ab, {1.0, 0.0, 0.0});
  const glm::dvec3 helper = std::abs(axis.x) < 0.9 ? glm::dvec3(1.0, 0.0, 0.0) : glm::dvec3(0.0, 1.0, 0.0);
  const glm::dvec3 perpendicular = glm::normalize(glm::cross(axis, helper));
  return {glm::length(toP) - radius_, directionOr(toP, perpendicular)};
}

Aabb CapsuleSource::bounds() const { return {glm::min(a_, b_) - radius_, glm::max(a_, b_) + radius_}; }

SdfSample smoothMin(const SdfSample& a, const SdfSample& b, double k) {
  const double w = std::clamp(0.5 + 0.5 * (b.value - a.value) / k, 0.0, 1.0);
  return {w * a.value + (1.0 - w) * b.value - k * w * (1.0 - w), w * a.gradient + (1.0 - w) * b.gradient};
}

SmoothUnionSource::SmoothUnionSource(std::vector<std::unique_ptr<SdfSource>> children, double blendRadius)
    : children_(std::move(children)), k_(blendRadius) {}

SdfSample SmoothUnionSource::sample(const glm::dvec3& p) const {
  if (children_.empty()) return {HUGE_VAL, glm::dvec3(0.0, 0.0, 1.0)};
  SdfSample result = children_.front()->sample(p);
  for (std::size_t i = 1; i < children_.size(); ++i) result = smoothMin(result, children_[i]->sample(p), k_);
  return result;
}

Aabb SmoothUnionSource::bounds() const {
  if (children_.empty()) return {};
  Aabb box = children_.front()->bounds();
  for (const auto& child : children_) {
    const Aabb b = child->bounds();
    box.min = glm::min(box.min, b.min);
    box.max = glm::max(box.max, b.max);
  }
  const double growth = children_.size() > 1 ? 0.25 * k_ : 0.0;
  return {box.min - growth, box.max + growth};
}

namespace {

std::unique_ptr<SdfSource> makeBlob() {
  std::vector<std::unique_ptr<SdfSource>> parts;
  parts.push_back(std::make_unique<SphereSource>(glm::dvec3(-0.35, 0.1, 0.0), 0.6));
  parts.push_back(std::make_unique<CapsuleSource>(glm::dvec3(0.0, -0.2, -0.1), glm::dvec3(0.9, 0.4, 0.3), 0.25));
  parts.push_back(std::make_unique<TorusSource>(glm::dvec3(0.2, -0.45, 0.1), 0.55, 0.15));
  return std::make_unique<SmoothUnionSource>(std::move(parts), 0.3);
}

using ShapeFactory = std::function<std::unique_ptr<SdfSource>()>;

const std::map<std::string, ShapeFactory, std::less<>>& shapeFactories() {
  static const std::map<std::string, ShapeFactory, std::less<>> factories = {
      {"sphere", [] { return std::make_unique<SphereSource>(glm::dvec3(0.0), 1.0); }},
      {"box", [] { return std::make_unique<BoxSource>(glm::dvec3(0.0), glm::dvec3(1.0, 0.7, 0.5)); }},
      {"torus", [] { return std::make_unique<TorusSource>(glm::dvec3(0.0), 1.0, 0.35); }},
      {"capsule",
       [] { return std::make_unique<CapsuleSource>(glm::dvec3(-0.8, -0.3, 0.0), glm::dvec3(0.8, 0.3, 0.0), 0.4); }},
      {"blob", makeBlob},
  };
  return factories;
}

}  // namespace

const std::vector<std::string>& analyticShapeNames() {
  static const std::vector<std::string> names = [] {
    std::vector<std::string> out;
    for (const auto& [name, factory] : shapeFactories()) out.push_back(name);
    return out;
  }();
  return names;
}

engine::Expected<std::unique_ptr<SdfSource>> makeAnalyticSource(std::string_view name) {
  const auto& factories = shapeFactories();
  const auto it = factories.find(name);
  if (it == factories.end())
    return engine::makeError(
        fmt::format("unknown analytic shape '{}' (known: {})", name, fmt::join(analyticShapeNames(), ", ")));
  return it->second();
}

}  // namespace hsdf
