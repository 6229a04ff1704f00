// Transform hierarchy: local matrices, parent-first resolution in any creation order, deep chains,
// and broken hierarchies (dangling parents, cycles) that must neither hang nor crash.
#include "engine/scene/transform.h"

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include <glm/gtc/matrix_transform.hpp>
#include <gtest/gtest.h>

#include "engine/core/log.h"
#include "log_capture.h"

namespace engine::scene {
namespace {

using ecs::Entity;

constexpr float kHalfPi = 1.57079632679f;

void expectMatrixNear(const glm::mat4& actual, const glm::mat4& expected, float tolerance = 1e-5f) {
  for (int c = 0; c < 4; ++c) {
    for (int r = 0; r < 4; ++r) EXPECT_NEAR(actual[c][r], expected[c][r], tolerance) << "column " << c << " row " << r;
  }
}

glm::vec3 transformPoint(const glm::mat4& m, const glm::vec3& p) { return glm::vec3(m * glm::vec4(p, 1.0f)); }

Entity makeNode(ecs::Registry& registry, const Transform& local, Entity parent = ecs::kNullEntity) {
  const Entity e = registry.create();
  registry.emplace<Transform>(e, local);
  if (!parent.isNull()) registry.emplace<Parent>(e, parent);
  return e;
}

// Tricky: the order scale -> rotate -> translate is checked on a point, where any other order gives
// a different answer (scale after rotation would stretch y instead of x; translation first would
// rotate the offset).
TEST(Transform, ToMatrixScalesThenRotatesThenTranslates) {
  Transform t;
  t.translation = glm::vec3(10.0f, 0.0f, 0.0f);
  t.rotation = glm::angleAxis(kHalfPi, glm::vec3(0.0f, 0.0f, 1.0f));  // +X -> +Y
  t.scale = glm::vec3(2.0f, 3.0f, 1.0f);
  const glm::vec3 p = transformPoint(toMatrix(t), glm::vec3(1.0f, 0.0f, 0.0f));
  EXPECT_NEAR(p.x, 10.0f, 1e-5f);
  EXPECT_NEAR(p.y, 2.0f, 1e-5f);
  EXPECT_NEAR(p.z, 0.0f, 1e-5f);
  expectMatrixNear(toMatrix(Transform{}), glm::mat4(1.0f));
}

// Tricky: children and grandchildren are created before their parents, so a single pass in storage
// order would read parents' world matrices before they are written.
// fromMatrix must invert toMatrix for any TRS, including the cases glm::decompose refuses: its
// absolute epsilon on the determinant turned a node scaled by 1e-3 (a millimetre export) into the
// identity, and a mirror must come back as a negative scale with a proper rotation.
TEST(Transform, FromMatrixInvertsToMatrixAtAnyScaleAndUnderMirroring) {
  const glm::quat rotations[] = {glm::quat(1.0f, 0.0f, 0.0f, 0.0f),
                                 glm::angleAxis(0.7f, glm::normalize(glm::vec3(1.0f, 2.0f, -0.5f))),
                                 glm::angleAxis(3.0f, glm::normalize(glm::vec3(-0.3f, 0.1f, 0.9f)))};
  const glm::vec3 scales[] = {glm::vec3(1.0f), glm::vec3(1e-3f), glm::vec3(1e-6f, 2e-6f, 5e-7f),
                              glm::vec3(1.0f, 2.5f, 0.4f), glm::vec3(-1.0f, 1.0f, 1.0f), glm::vec3(-1e-3f, 3e-3f, 2e-3f),
                              glm::vec3(1e4f)};
  for (const glm::quat& rotation : rotations)
    for (const glm::vec3& scale : scales) {
      const Transform original{glm::vec3(0.5f, -2.0f, 3.0f), rotation, scale};
      const glm::mat4 matrix = toMatrix(original);
      const Transform back = fromMatrix(matrix);
      const float size = std::max({std::abs(scale.x), std::abs(scale.y), std::abs(scale.z)});
      expectMatrixNear(toMatrix(back), matrix, 1e-5f * size);
      EXPECT_NEAR(glm::length(back.rotation), 1.0f, 1e-5f);
      EXPECT_EQ(back.scale.x < 0.0f, glm::determinant(glm::mat3(matrix)) < 0.0f);
    }
}

// A zero scale on one axis (an object flattened by an animation) keeps the other axes' rotation.
TEST(Transform, FromMatrixKeepsAFlattenedAxis) {
  const Transform original{glm::vec3(1.0f), glm::angleAxis(0.4f, glm::vec3(0.0f, 1.0f, 0.0f)), glm::vec3(2.0f, 0.0f, 3.0f)};
  const Transform back = fromMatrix(toMatrix(original));
  EXPECT_EQ(back.scale.y, 0.0f);
  expectMatrixNear(toMatrix(back), toMatrix(original), 1e-5f);
}

TEST(Transform, ParentsAreResolvedFirstWhateverTheCreationOrder) {
  ecs::Registry registry;
  const Entity grandchild = registry.create();
  const Entity child = registry.create();
  const Entity root = registry.create();
  Transform rootLocal;
  rootLocal.translation = {5.0f, 0.0f, 0.0f};
  rootLocal.rotation = glm::angleAxis(kHalfPi, glm::vec3(0.0f, 1.0f, 0.0f));
  Transform childLocal;
  childLocal.translation = {0.0f, 0.0f, 2.0f};
  childLocal.scale = glm::vec3(3.0f);
  Transform grandchildLocal;
  grandchildLocal.translation = {1.0f, 1.0f, 0.0f};
  registry.emplace<Transform>(grandchild, grandchildLocal);
  registry.emplace<Parent>(grandchild, child);
  registry.emplace<Transform>(child, childLocal);
  registry.emplace<Parent>(child, root);
  registry.emplace<Transform>(root, rootLocal);

  const HierarchyIssues issues = updateWorldTransforms(registry);
  EXPECT_EQ(issues.danglingParents, 0u);
  EXPECT_EQ(issues.cycleMembers, 0u);

  const glm::mat4 rootWorld = toMatrix(rootLocal);
  const glm::mat4 childWorld = rootWorld * toMatrix(childLocal);
  expectMatrixNear(registry.get<WorldTransform>(root).matrix, rootWorld);
  expectMatrixNear(registry.get<WorldTransform>(child).matrix, childWorld);
  expectMatrixNear(registry.get<WorldTransform>(grandchild).matrix, childWorld * toMatrix(grandchildLocal));
  // Independent check of one point: grandchild origin = root(child(translation)).
  // child origin: root rotates (0,0,2) about Y by 90 deg -> (2,0,0), plus (5,0,0) = (7,0,0);
  // grandchild offset (1,1,0) scaled by 3 -> (3,3,0), rotated -> (0,3,-3).
  const glm::vec3 origin = transformPoint(registry.get<WorldTransform>(grandchild).matrix, glm::vec3(0.0f));
  EXPECT_NEAR(origin.x, 7.0f, 1e-5f);
  EXPECT_NEAR(origin.y, 3.0f, 1e-5f);
  EXPECT_NEAR(origin.z, -3.0f, 1e-5f);
}

// Tricky: a 100k-deep chain created leaf first; a recursive resolver would overflow the stack and a
// resolver that re-walks ancestors per entity would take quadratic time.
TEST(Transform, DeepChainCreatedLeafFirst) {
  constexpr int kDepth = 100000;
  ecs::Registry registry;
  std::vector<Entity> chain(kDepth);
  for (int i = kDepth - 1; i >= 0; --i) chain[static_cast<std::size_t>(i)] = registry.create();
  Transform step;
  step.translation = {1.0f, 0.0f, 0.0f};
  for (int i = 0; i < kDepth; ++i) {
    registry.emplace<Transform>(chain[static_cast<std::size_t>(i)], step);
    if (i > 0) registry.emplace<Parent>(chain[static_cast<std::size_t>(i)], chain[static_cast<std::size_t>(i - 1)]);
  }
  updateWorldTransforms(registry);
  // Integer translations add exactly in float, so depth d sits at x = d + 1.
  EXPECT_EQ(registry.get<WorldTransform>(chain.back()).matrix[3].x, static_cast<float>(kDepth));
  EXPECT_EQ(registry.get<WorldTransform>(chain[12345]).matrix[3].x, 12346.0f);
}

// Tricky: results must come from the current Parent and Transform, not from anything cached by a
// previous call, and an existing (stale) WorldTransform must be overwritten.
TEST(Transform, ReparentingAndEditsTakeEffectOnTheNextUpdate) {
  ecs::Registry registry;
  Transform a;
  a.translation = {1.0f, 0.0f, 0.0f};
  Transform b;
  b.translation = {0.0f, 10.0f, 0.0f};
  const Entity parentA = makeNode(registry, a);
  const Entity parentB = makeNode(registry, b);
  const Entity child = makeNode(registry, Transform{}, parentA);
  registry.emplace<WorldTransform>(child, glm::mat4(7.0f));  // stale garbage

  updateWorldTransforms(registry);
  EXPECT_EQ(glm::vec3(registry.get<WorldTransform>(child).matrix[3]), glm::vec3(1.0f, 0.0f, 0.0f));

  registry.get<Parent>(child).entity = parentB;
  registry.get<Transform>(parentB).translation.z = 3.0f;
  updateWorldTransforms(registry);
  EXPECT_EQ(glm::vec3(registry.get<WorldTransform>(child).matrix[3]), glm::vec3(0.0f, 10.0f, 3.0f));

  registry.remove<Parent>(child);
  updateWorldTransforms(registry);
  expectMatrixNear(registry.get<WorldTransform>(child).matrix, glm::mat4(1.0f));
}

// Tricky: a Parent on an entity without Transform is not part of the hierarchy: it must be left
// alone rather than given a WorldTransform.
TEST(Transform, EntitiesWithoutTransformAreUntouched) {
  ecs::Registry registry;
  const Entity root = makeNode(registry, Transform{});
  const Entity bare = registry.create();
  registry.emplace<Parent>(bare, root);
  updateWorldTransforms(registry);
  EXPECT_TRUE(registry.has<WorldTransform>(root));
  EXPECT_FALSE(registry.has<WorldTransform>(bare));
}

// Tricky: the parent handle is dead (its index even reused by a new entity with a Transform, which
// must not be mistaken for the parent), or alive without a Transform. Both become roots, and the
// warning names the entity once, not on every frame.
TEST(Transform, DanglingParentsBecomeRootsAndWarnOnce) {
  hsdftest::LogCapture warnings;
  ecs::Registry registry;
  Transform offset;
  offset.translation = {0.0f, 0.0f, 4.0f};
  const Entity doomed = makeNode(registry, offset);
  Transform childLocal;
  childLocal.translation = {1.0f, 2.0f, 3.0f};
  const Entity orphan = makeNode(registry, childLocal, doomed);
  registry.emplace<Name>(orphan, "orphan");
  registry.destroy(doomed);
  const Entity impostor = makeNode(registry, offset);  // reuses doomed's index
  ASSERT_EQ(impostor.index, doomed.index);

  const Entity noTransform = registry.create();
  const Entity stepChild = makeNode(registry, childLocal, noTransform);

  HierarchyIssues issues = updateWorldTransforms(registry);
  EXPECT_EQ(issues.danglingParents, 2u);
  EXPECT_EQ(issues.cycleMembers, 0u);
  expectMatrixNear(registry.get<WorldTransform>(orphan).matrix, toMatrix(childLocal));
  expectMatrixNear(registry.get<WorldTransform>(stepChild).matrix, toMatrix(childLocal));
  ASSERT_EQ(warnings.messages().size(), 1u);
  EXPECT_NE(warnings.messages()[0].find("orphan"), std::string::npos) << warnings.messages()[0];
  EXPECT_NE(warnings.messages()[0].find(fmt::format("{}", stepChild)), std::string::npos) << warnings.messages()[0];

  issues = updateWorldTransforms(registry);
  EXPECT_EQ(issues.danglingParents, 2u) << "still counted on every call";
  EXPECT_EQ(warnings.messages().size(), 1u) << "but not warned about again";

  registry.get<Parent>(orphan).entity = noTransform;  // broken differently: worth a new warning
  updateWorldTransforms(registry);
  EXPECT_EQ(warnings.messages().size(), 2u);
}

// Tricky: a two-cycle, a self-parent, and a child hanging off the cycle. The update must terminate,
// make every cycle member a root regardless of which one the walk reaches first, and still give the
// hanging child its member's world matrix.
TEST(Transform, CyclesTerminateAndTheirMembersBecomeRoots) {
  hsdftest::LogCapture warnings;
  ecs::Registry registry;
  Transform la;
  la.translation = {1.0f, 0.0f, 0.0f};
  Transform lb;
  lb.translation = {0.0f, 2.0f, 0.0f};
  Transform lc;
  lc.translation = {0.0f, 0.0f, 3.0f};
  // The hanging child's Transform comes first in storage, so the walk enters the cycle from outside.
  const Entity hanging = registry.create();
  registry.emplace<Transform>(hanging, lc);
  const Entity a = makeNode(registry, la);
  const Entity b = makeNode(registry, lb, a);
  registry.emplace<Parent>(a, b);
  registry.emplace<Parent>(hanging, b);
  const Entity self = makeNode(registry, la);
  registry.emplace<Parent>(self, self);

  const HierarchyIssues issues = updateWorldTransforms(registry);
  EXPECT_EQ(issues.cycleMembers, 3u);
  EXPECT_EQ(issues.danglingParents, 0u);
  expectMatrixNear(registry.get<WorldTransform>(a).matrix, toMatrix(la));
  expectMatrixNear(registry.get<WorldTransform>(b).matrix, toMatrix(lb));
  expectMatrixNear(registry.get<WorldTransform>(self).matrix, toMatrix(la));
  expectMatrixNear(registry.get<WorldTransform>(hanging).matrix, toMatrix(lb) * toMatrix(lc));
  ASSERT_EQ(warnings.messages().size(), 1u);
  EXPECT_NE(warnings.messages()[0].find("cycle"), std::string::npos) << warnings.messages()[0];

  updateWorldTransforms(registry);
  EXPECT_EQ(warnings.messages().size(), 1u);
}

}  // namespace
}  // namespace engine::scene
