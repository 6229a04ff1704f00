// Keyframe evaluation against values worked by hand from the glTF 2.0 spec's formulas.
#include "engine/scene/animation.h"

#include <gtest/gtest.h>

#include <cmath>

#include <glm/gtc/matrix_transform.hpp>

#include "engine/scene/scene_pose.h"

namespace engine::scene {
namespace {

constexpr float kTolerance = 1e-5f;

void expectNear(const glm::vec4& actual, const glm::vec4& expected, const char* what) {
  for (int c = 0; c < 4; ++c) EXPECT_NEAR(actual[c], expected[c], kTolerance) << what << " component " << c;
}

// The same rotation whichever sign the quaternion comes with.
void expectSameRotation(const glm::vec4& actual, const glm::vec4& expected, const char* what) {
  expectNear(glm::dot(actual, expected) < 0.0f ? -actual : actual, expected, what);
}

glm::vec4 aboutZ(float degrees) {
  const float half = glm::radians(degrees) * 0.5f;
  return {0.0f, 0.0f, std::sin(half), std::cos(half)};
}

AnimationSampler sampler(Interpolation interpolation, std::vector<float> times, std::vector<glm::vec4> values) {
  return AnimationSampler{std::move(times), std::move(values), interpolation};
}

TEST(AnimationSample, StepHoldsEachKeyUntilTheNext) {
  const auto s = sampler(Interpolation::Step, {0, 1, 2}, {{1, 0, 0, 0}, {2, 0, 0, 0}, {3, 0, 0, 0}});
  EXPECT_EQ(sampleAt(s, 0.5f, false).x, 1.0f);
  EXPECT_EQ(sampleAt(s, 1.0f, false).x, 2.0f);
  EXPECT_EQ(sampleAt(s, 1.99f, false).x, 2.0f);
  EXPECT_EQ(sampleAt(s, 2.0f, false).x, 3.0f);
}

// Before the first key the first value, after the last the last: glTF viewers clamp, they do not extrapolate.
TEST(AnimationSample, LinearHitsEndpointsAndMidpointAndClampsOutside) {
  const auto s = sampler(Interpolation::Linear, {1, 3}, {{0, 0, 0, 0}, {4, 2, -2, 0}});
  expectNear(sampleAt(s, 1.0f, false), {0, 0, 0, 0}, "first key");
  expectNear(sampleAt(s, 2.0f, false), {2, 1, -1, 0}, "midpoint");
  expectNear(sampleAt(s, 2.5f, false), {3, 1.5f, -1.5f, 0}, "three quarters");
  expectNear(sampleAt(s, 3.0f, false), {4, 2, -2, 0}, "last key");
  expectNear(sampleAt(s, -5.0f, false), {0, 0, 0, 0}, "before the first key");
  expectNear(sampleAt(s, 9.0f, false), {4, 2, -2, 0}, "after the last key");
}

// A quarter of the way from 0 to 120 degrees is 30 degrees by slerp; a normalized lerp gives 27.6.
TEST(AnimationSample, LinearRotationSlerps) {
  const auto s = sampler(Interpolation::Linear, {0, 1}, {aboutZ(0), aboutZ(120)});
  expectSameRotation(sampleAt(s, 0.25f, true), aboutZ(30), "slerp at 1/4");
}

// q and -q are one rotation: from 0 to -(90 degrees) the short way passes 45 degrees, not 225.
TEST(AnimationSample, LinearRotationTakesTheShortestPathAcrossASignFlip) {
  const auto s = sampler(Interpolation::Linear, {0, 1}, {aboutZ(0), -aboutZ(90)});
  expectSameRotation(sampleAt(s, 0.5f, true), aboutZ(45), "midpoint");
}

// Keys at t = 0 and 2 (interval h = 2): at u = 1/2 the spec's cubic is
// 0.5 v0 + 0.125 h b0 + 0.5 v1 - 0.125 h a1 = 0.5 (4,0,0) + 0.25 (1,0,0) - 0.25 (0,3,0) = (2.25, -0.75, 0).
TEST(AnimationSample, CubicSplineScalesTangentsByTheKeyInterval) {
  const glm::vec4 unused(9.0f);
  const auto s = sampler(Interpolation::CubicSpline, {0, 2},
                         {unused, {0, 0, 0, 0}, {1, 0, 0, 0}, {0, 3, 0, 0}, {4, 0, 0, 0}, unused});
  expectNear(sampleAt(s, 1.0f, false), {2.25f, -0.75f, 0, 0}, "u = 1/2");
  expectNear(sampleAt(s, 0.0f, false), {0, 0, 0, 0}, "first key's value, not a tangent");
  expectNear(sampleAt(s, 2.0f, false), {4, 0, 0, 0}, "last key's value, not a tangent");
}

TEST(AnimationSample, CubicSplineRotationIsNormalized) {
  const glm::vec4 zero(0.0f);
  const auto s = sampler(Interpolation::CubicSpline, {0, 1}, {zero, aboutZ(0), zero, zero, aboutZ(90), zero});
  const glm::vec4 q = sampleAt(s, 0.5f, true);
  EXPECT_NEAR(glm::length(q), 1.0f, kTolerance);
  expectSameRotation(q, aboutZ(45), "halfway between two keys with zero tangents");
}

// A channel replaces its part only: the node's rest scale stays under a translation channel.
TEST(AnimationPose, ChannelsReplaceOnlyTheirPart) {
  AnimationData animation;
  animation.samplers.push_back(sampler(Interpolation::Linear, {0, 2}, {{0, 0, 0, 0}, {2, 4, 6, 0}}));
  animation.channels.push_back(AnimationChannel{0, 1, AnimatedPath::Translation});
  std::vector<NodePose> rest(2);
  rest[1].scale = glm::vec3(3.0f);
  const std::vector<NodePose> pose = poseAt(animation, rest, 1.0f);
  EXPECT_EQ(pose[1].translation, glm::vec3(1, 2, 3));
  EXPECT_EQ(pose[1].scale, glm::vec3(3.0f));
  EXPECT_EQ(pose[0].translation, glm::vec3(0.0f));
}

TEST(AnimationPose, LoopTimeWrapsAtTheLastKey) {
  AnimationData animation;
  animation.samplers.push_back(sampler(Interpolation::Step, {0, 2}, {{}, {}}));
  EXPECT_FLOAT_EQ(loopTime(animation, 5.0f), 1.0f);
  EXPECT_FLOAT_EQ(loopTime(animation, 1.5f), 1.5f);
}

// The child follows its animated parent (world = parent world x child local); posing twice at the
// same time gives the same matrices (each pose starts from the rest pose, never from the last one).
TEST(AnimationPose, PoseSceneMovesChildrenWithTheirAnimatedParent) {
  SceneData scene;
  scene.nodes.resize(2);
  scene.nodes[1].parent = 0;
  scene.nodes[1].local = glm::translate(glm::mat4(1.0f), glm::vec3(1, 0, 0));
  scene.nodes[1].world = scene.nodes[1].local;
  AnimationData animation;
  animation.samplers.push_back(sampler(Interpolation::Linear, {0, 1}, {aboutZ(0), aboutZ(90)}));
  animation.channels.push_back(AnimationChannel{0, 0, AnimatedPath::Rotation});
  const RestPose rest = restPose(scene);
  poseScene(scene, rest, animation, 1.0f);
  poseScene(scene, rest, animation, 1.0f);
  const glm::vec4 childOrigin = scene.nodes[1].world * glm::vec4(0, 0, 0, 1);
  expectNear(childOrigin, {0, 1, 0, 1}, "child at +x turned 90 degrees about z");
  EXPECT_EQ(scene.nodes[1].local, rest.locals[1]) << "a node no channel drives keeps its exact matrix";
}

}  // namespace
}  // namespace engine::scene
