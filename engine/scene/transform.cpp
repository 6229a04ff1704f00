#include "engine/scene/transform.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include <glm/gtc/matrix_transform.hpp>

#include "engine/core/log.h"

namespace engine::scene {

glm::mat4 toMatrix(const Transform& transform) {
  return glm::translate(glm::mat4(1.0f), transform.translation) * glm::mat4_cast(transform.rotation) *
         glm::scale(glm::mat4(1.0f), transform.scale);
}

Transform fromMatrix(const glm::mat4& matrix) {
  Transform transform;
  transform.translation = glm::vec3(matrix[3]);
  glm::mat3 axes(matrix);
  for (int i = 0; i < 3; ++i) transform.scale[i] = glm::length(axes[i]);
  if (glm::determinant(axes) < 0.0f) transform.scale.x = -transform.scale.x;
  // Normalized columns; a zero column is rebuilt from the other two so the rotation stays proper.
  bool degenerate = false;
  for (int i = 0; i < 3; ++i) {
    if (transform.scale[i] != 0.0f && std::isfinite(transform.scale[i])) axes[i] /= transform.scale[i];
    else degenerate = true;
  }
  if (degenerate) {
    const bool x = transform.scale.x != 0.0f, y = transform.scale.y != 0.0f, z = transform.scale.z != 0.0f;
    if (x && y) axes[2] = glm::normalize(glm::cross(axes[0], axes[1]));
    else if (y && z) axes[0] = glm::normalize(glm::cross(axes[1], axes[2]));
    else if (x && z) axes[1] = glm::normalize(glm::cross(axes[2], axes[0]));
    else axes = glm::mat3(1.0f);
    if (!std::isfinite(glm::determinant(axes))) axes = glm::mat3(1.0f);
  }
  transform.rotation = glm::normalize(glm::quat_cast(axes));
  return transform;
}

namespace {

// Remembers that an entity was warned about while it had this parent, so a broken hierarchy that is
// updated every frame is reported once rather than every frame.
struct HierarchyWarning {
  ecs::Entity parent;
};

enum class Mark : std::uint8_t { Unvisited, InProgress, Done };

class HierarchyResolver {
 public:
  explicit HierarchyResolver(ecs::Registry& registry)
      : registry_(registry), marks_(registry.indexBound(), Mark::Unvisited) {}

  void resolve(ecs::Entity entity);
  const HierarchyIssues& issues() const { return issues_; }
  void logNewWarnings() const;

 private:
  // Walks up from `entity` pushing unresolved ancestors onto chain_; returns the world matrix the
  // topmost of them hangs from.
  glm::mat4 collectUnresolvedChain(ecs::Entity entity);
  glm::mat4 breakCycleAt(std::vector<ecs::Entity>::iterator cycleStart);
  void setWorld(ecs::Entity entity, const glm::mat4& world);
  void noteBrokenParent(ecs::Entity entity, std::vector<ecs::Entity>& newlyWarned);
  Mark& mark(ecs::Entity entity) { return marks_[entity.index]; }

  ecs::Registry& registry_;
  std::vector<Mark> marks_;  // by entity index
  std::vector<ecs::Entity> chain_;
  HierarchyIssues issues_;
  std::vector<ecs::Entity> newDangling_;
  std::vector<ecs::Entity> newCycleMembers_;
};

void HierarchyResolver::resolve(ecs::Entity entity) {
  if (mark(entity) == Mark::Done) return;
  chain_.clear();
  glm::mat4 world = collectUnresolvedChain(entity);
  // chain_ runs child -> ancestor; resolve from the top down.
  for (auto it = chain_.rbegin(); it != chain_.rend(); ++it) {
    world = world * toMatrix(registry_.get<Transform>(*it));
    setWorld(*it, world);
  }
}

glm::mat4 HierarchyResolver::collectUnresolvedChain(ecs::Entity entity) {
  ecs::Entity current = entity;
  while (true) {
    mark(current) = Mark::InProgress;
    chain_.push_back(current);
    const Parent* parent = registry_.tryGet<Parent>(current);
    if (parent == nullptr) return glm::mat4(1.0f);
    const ecs::Entity up = parent->entity;
    if (!registry_.valid(up) || !registry_.has<Transform>(up)) {
      ++issues_.danglingParents;
      noteBrokenParent(current, newDangling_);
      return glm::mat4(1.0f);
    }
    if (mark(up) == Mark::Done) return registry_.get<WorldTransform>(up).matrix;
    if (mark(up) == Mark::InProgress) return breakCycleAt(std::find(chain_.begin(), chain_.end(), up));
    current = up;
  }
}

// Every member of the cycle (chain_ from cycleStart on) becomes a root; the chain below it inherits
// from the member it hangs from.
glm::mat4 HierarchyResolver::breakCycleAt(std::vector<ecs::Entity>::iterator cycleStart) {
  for (auto it = cycleStart; it != chain_.end(); ++it) {
    ++issues_.cycleMembers;
    noteBrokenParent(*it, newCycleMembers_);
    setWorld(*it, toMatrix(registry_.get<Transform>(*it)));
  }
  const glm::mat4 base = registry_.get<WorldTransform>(*cycleStart).matrix;
  chain_.erase(cycleStart, chain_.end());
  return base;
}

void HierarchyResolver::setWorld(ecs::Entity entity, const glm::mat4& world) {
  registry_.emplaceOrReplace<WorldTransform>(entity, world);
  mark(entity) = Mark::Done;
}

void HierarchyResolver::noteBrokenParent(ecs::Entity entity, std::vector<ecs::Entity>& newlyWarned) {
  const ecs::Entity parent = registry_.get<Parent>(entity).entity;
  const HierarchyWarning* previous = registry_.tryGet<HierarchyWarning>(entity);
  if (previous != nullptr && previous->parent == parent) return;
  registry_.emplaceOrReplace<HierarchyWarning>(entity, parent);
  newlyWarned.push_back(entity);
}

std::string describeEntities(const ecs::Registry& registry, const std::vector<ecs::Entity>& entities) {
  constexpr std::size_t kListed = 5;
  std::string text;
  for (std::size_t i = 0; i < std::min(entities.size(), kListed); ++i) {
    const Name* name = registry.tryGet<Name>(entities[i]);
    text += fmt::format("{}{}", i == 0 ? "" : ", ", entities[i]);
    if (name != nullptr) text += fmt::format(" '{}'", name->value);
  }
  if (entities.size() > kListed) text += fmt::format(", ... ({} more)", entities.size() - kListed);
  return text;
}

void HierarchyResolver::logNewWarnings() const {
  if (!newDangling_.empty()) {
    log::warn("transform hierarchy: {} entities have a dead parent or one without a Transform; treated as roots: {}",
              newDangling_.size(), describeEntities(registry_, newDangling_));
  }
  if (!newCycleMembers_.empty()) {
    log::warn("transform hierarchy: {} entities form parent cycles; each treated as a root: {}",
              newCycleMembers_.size(), describeEntities(registry_, newCycleMembers_));
  }
}

}  // namespace

HierarchyIssues updateWorldTransforms(ecs::Registry& registry) {
  HierarchyResolver resolver(registry);
  for (const ecs::Entity entity : registry.view<Transform>()) resolver.resolve(entity);
  resolver.logNewWarnings();
  return resolver.issues();
}

}  // namespace engine::scene
