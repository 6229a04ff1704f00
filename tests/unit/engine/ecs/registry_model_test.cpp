// Model-based randomized test: many thousands of random registry operations, checked against a
// std::map reference model. Fixed seeds, so a failure reproduces.
#include <cstdint>
#include <map>
#include <optional>
#include <random>
#include <set>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "engine/ecs/registry.h"

namespace engine::ecs {
namespace {

struct Health {
  int value = 0;
};

struct ModelEntity {
  std::optional<Health> health;
  std::optional<std::string> label;  // heap-allocated strings, so moves and destructors matter
};

class RegistryModelTest : public ::testing::TestWithParam<std::uint32_t> {
 protected:
  // Any handle ever issued, alive or dead: dead ones must be rejected everywhere.
  Entity pickAnyHandle() { return issued_[random_() % issued_.size()]; }
  std::string randomLabel() { return std::string(16 + random_() % 32, static_cast<char>('a' + random_() % 26)); }

  void step();
  void checkEverything();

  std::mt19937 random_{GetParam()};
  Registry registry_;
  std::map<Entity, ModelEntity> model_;
  std::vector<Entity> issued_;
};

void RegistryModelTest::step() {
  const auto operation = static_cast<std::uint32_t>(random_() % 100);
  if (model_.empty() || operation < 25) {
    const Entity e = registry_.create();
    ASSERT_TRUE(model_.find(e) == model_.end()) << "handle " << e.index << ":" << e.generation << " issued twice";
    model_[e] = {};
    issued_.push_back(e);
    return;
  }
  const Entity any = pickAnyHandle();
  const bool alive = model_.count(any) != 0;
  if (operation < 35) {
    EXPECT_EQ(registry_.destroy(any), alive);
    model_.erase(any);
  } else if (operation < 55) {
    const int value = static_cast<int>(random_() % 1000);
    if (!alive) {
      EXPECT_THROW(registry_.emplaceOrReplace<Health>(any, value), std::logic_error);
    } else {
      registry_.emplaceOrReplace<Health>(any, value);
      model_[any].health = Health{value};
    }
  } else if (operation < 70) {
    if (alive && !model_[any].label) {
      std::string label = randomLabel();
      registry_.emplace<std::string>(any, label);
      model_[any].label = label;
    } else {
      EXPECT_THROW(registry_.emplace<std::string>(any, "x"), std::logic_error);
    }
  } else if (operation < 80) {
    EXPECT_EQ(registry_.remove<Health>(any), alive && model_[any].health.has_value());
    if (alive) model_[any].health.reset();
  } else if (operation < 90) {
    EXPECT_EQ(registry_.remove<std::string>(any), alive && model_[any].label.has_value());
    if (alive) model_[any].label.reset();
  } else {
    const Health* health = registry_.tryGet<Health>(any);
    const bool modelHas = alive && model_[any].health.has_value();
    ASSERT_EQ(health != nullptr, modelHas);
    if (modelHas) {
      EXPECT_EQ(health->value, model_[any].health->value);
    }
  }
}

void RegistryModelTest::checkEverything() {
  std::size_t healthCount = 0;
  std::size_t labelCount = 0;
  std::set<Entity> expectedBoth;
  for (const auto& [e, state] : model_) {
    ASSERT_TRUE(registry_.valid(e));
    const Health* health = registry_.tryGet<Health>(e);
    ASSERT_EQ(health != nullptr, state.health.has_value());
    if (health != nullptr) {
      EXPECT_EQ(health->value, state.health->value);
    }
    const std::string* label = registry_.tryGet<std::string>(e);
    ASSERT_EQ(label != nullptr, state.label.has_value());
    if (label != nullptr) {
      EXPECT_EQ(*label, *state.label);
    }
    healthCount += state.health ? 1 : 0;
    labelCount += state.label ? 1 : 0;
    if (state.health && state.label) expectedBoth.insert(e);
  }
  for (const Entity e : issued_) EXPECT_EQ(registry_.valid(e), model_.count(e) != 0);
  EXPECT_EQ(registry_.alive(), model_.size());
  EXPECT_EQ(registry_.size<Health>(), healthCount);
  EXPECT_EQ(registry_.size<std::string>(), labelCount);

  std::set<Entity> visited;
  registry_.view<Health, std::string>().each([&](Entity e, const Health& health, const std::string& label) {
    EXPECT_TRUE(visited.insert(e).second);
    EXPECT_EQ(health.value, model_.at(e).health->value);
    EXPECT_EQ(label, *model_.at(e).label);
  });
  EXPECT_EQ(visited, expectedBoth);
}

// Tricky: 120k interleaved creates, destroys (including stale handles), emplaces, replaces and
// removes over tens of thousands of live entities spanning many sparse pages; every swap-and-pop and
// index reuse must keep the registry identical to the model.
TEST_P(RegistryModelTest, MatchesReferenceModel) {
  constexpr int kSteps = 120000;
  constexpr int kCheckEvery = 20000;
  for (int i = 1; i <= kSteps; ++i) {
    step();
    if (HasFatalFailure()) return;
    if (i % kCheckEvery == 0) {
      checkEverything();
      if (HasFatalFailure()) return;
    }
  }
  EXPECT_GT(model_.size(), 10000u) << "the walk should build a large registry";
  // Tear down most of it through destroy and check the rest again.
  std::vector<Entity> alive;
  for (const auto& entry : model_) alive.push_back(entry.first);
  for (std::size_t i = 0; i < alive.size(); i += 2) {
    registry_.destroy(alive[i]);
    model_.erase(alive[i]);
  }
  checkEverything();
}

INSTANTIATE_TEST_SUITE_P(Seeds, RegistryModelTest, ::testing::Values(1u, 20240601u));

}  // namespace
}  // namespace engine::ecs
