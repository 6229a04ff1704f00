#pragma once
// Transform hierarchy components and the pass that resolves them into world matrices.
#include <cstddef>
#include <string>

#include <glm/glm.hpp>
#include <glm/gtc/quaternion.hpp>

#include "engine/ecs/registry.h"

namespace engine::scene {

// Local transform relative to the parent (or the world for roots): scale, then rotate, then translate.
// `rotation` is expected to be a unit quaternion.
struct Transform {
  glm::vec3 translation{0.0f};
  glm::quat rotation{1.0f, 0.0f, 0.0f, 0.0f};  // w, x, y, z: identity
  glm::vec3 scale{1.0f};
};

struct Parent {
  ecs::Entity entity;
};

// Written by updateWorldTransforms; read by the renderer.
struct WorldTransform {
  glm::mat4 matrix{1.0f};
};

struct Name {
  std::string value;
};

// translate(translation) * rotate(rotation) * scale(scale).
glm::mat4 toMatrix(const Transform& transform);

// The inverse of toMatrix for an affine TRS matrix (what glTF node matrices are by specification):
// scales are the column lengths, a mirroring matrix (negative determinant) gets a negative x scale,
// and the rotation is that of the normalized columns. Unlike glm::decompose it has no absolute
// epsilon, so a node scaled by 1e-3 (millimetres to metres) keeps its scale. A column of length
// zero keeps scale 0 (the object has no volume and is not drawn) with the rotation of the others;
// a matrix with shear gets the nearest rotation the normalized columns give (not exact).
Transform fromMatrix(const glm::mat4& matrix);

// Entities that updateWorldTransforms treated as roots because their hierarchy is broken.
struct HierarchyIssues {
  std::size_t danglingParents = 0;  // Parent names a dead entity or one without a Transform
  std::size_t cycleMembers = 0;     // entities on a parent cycle
};

// Sets WorldTransform (emplacing it where missing) of every entity that has a Transform:
// parent's world matrix * toMatrix(local), parents resolved first whatever the creation order, with
// no recursion (chains of any depth). A dangling parent makes the entity a root; every member of a
// parent cycle becomes a root (entities hanging off the cycle still inherit from their member). Each
// such entity is reported in a warning once (until its Parent changes), not on every call.
HierarchyIssues updateWorldTransforms(ecs::Registry& registry);

}  // namespace engine::scene
