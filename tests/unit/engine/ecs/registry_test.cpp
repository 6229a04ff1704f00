// Registry basics: entity lifetime and generations, component add/get/remove, error policy.
#include "engine/ecs/registry.h"

#include <memory>
#include <stdexcept>
#include <string>
#include <unordered_set>
#include <vector>

#include <gtest/gtest.h>

namespace engine::ecs {
namespace {

struct Position {
  float x = 0.0f;
  float y = 0.0f;
};

// Counts live instances so leaks and double destruction show up as a wrong count.
struct Tracked {
  static inline int live = 0;
  int value = 0;
  explicit Tracked(int v) : value(v) { ++live; }
  Tracked(const Tracked& other) : value(other.value) { ++live; }
  Tracked(Tracked&& other) noexcept : value(other.value) { ++live; }
  Tracked& operator=(const Tracked&) = default;
  Tracked& operator=(Tracked&&) noexcept = default;
  ~Tracked() { --live; }
};

// Tricky: a default Entity must be the null one and never valid, even in a registry whose slot 0 is alive.
TEST(Registry, NullEntityIsNeverValid) {
  Registry registry;
  const Entity first = registry.create();
  EXPECT_EQ(first.index, 0u);
  EXPECT_FALSE(registry.valid(Entity{}));
  EXPECT_FALSE(registry.valid(kNullEntity));
  EXPECT_TRUE(kNullEntity.isNull());
  EXPECT_FALSE(registry.destroy(kNullEntity));
  EXPECT_EQ(registry.alive(), 1u);
}

// Tricky: the reused index must come back with a new generation, and the old handle (same index)
// must neither be valid nor able to destroy the entity that now occupies the slot.
TEST(Registry, DestroyedIndexIsReusedWithNewGeneration) {
  Registry registry;
  const Entity a = registry.create();
  const Entity b = registry.create();
  EXPECT_NE(a, b);
  EXPECT_EQ(registry.alive(), 2u);

  EXPECT_TRUE(registry.destroy(a));
  EXPECT_FALSE(registry.valid(a));
  EXPECT_EQ(registry.alive(), 1u);

  const Entity reused = registry.create();
  EXPECT_EQ(reused.index, a.index);
  EXPECT_NE(reused.generation, a.generation);
  EXPECT_TRUE(registry.valid(reused));
  EXPECT_FALSE(registry.valid(a));

  EXPECT_FALSE(registry.destroy(a));  // stale: must not touch `reused`
  EXPECT_TRUE(registry.valid(reused));
  EXPECT_TRUE(registry.valid(b));
  EXPECT_EQ(registry.alive(), 2u);
}

// Tricky: every generation of one slot stays dead forever, not just the one just before the current.
TEST(Registry, EveryOldGenerationOfASlotStaysInvalid) {
  Registry registry;
  std::vector<Entity> history;
  for (int i = 0; i < 50; ++i) {
    history.push_back(registry.create());
    registry.destroy(history.back());
  }
  const Entity current = registry.create();
  for (const Entity old : history) {
    EXPECT_EQ(old.index, current.index);
    EXPECT_FALSE(registry.valid(old));
  }
  EXPECT_TRUE(registry.valid(current));
}

// Tricky: a stale handle shares its index with a live entity that has the same component type, so
// a storage that compared indices only would answer for the wrong entity.
TEST(Registry, StaleHandleSeesNoComponents) {
  Registry registry;
  const Entity old = registry.create();
  registry.emplace<int>(old, 5);
  registry.destroy(old);
  const Entity current = registry.create();
  ASSERT_EQ(current.index, old.index);
  registry.emplace<int>(current, 7);

  EXPECT_FALSE(registry.has<int>(old));
  EXPECT_EQ(registry.tryGet<int>(old), nullptr);
  EXPECT_THROW(registry.get<int>(old), std::logic_error);
  EXPECT_THROW(registry.emplace<int>(old, 1), std::logic_error);
  EXPECT_THROW(registry.emplaceOrReplace<int>(old, 1), std::logic_error);
  EXPECT_FALSE(registry.remove<int>(old));
  EXPECT_EQ(registry.get<int>(current), 7);
  EXPECT_EQ(registry.size<int>(), 1u);
}

TEST(Registry, EmplaceGetRemove) {
  Registry registry;
  const Entity e = registry.create();
  EXPECT_FALSE(registry.has<Position>(e));
  EXPECT_EQ(registry.size<Position>(), 0u);  // never-used type: no storage yet

  Position& position = registry.emplace<Position>(e, 1.0f, 2.0f);
  position.x = 3.0f;  // the returned reference is the stored component
  EXPECT_TRUE(registry.has<Position>(e));
  EXPECT_EQ(registry.get<Position>(e).x, 3.0f);
  EXPECT_EQ(registry.get<Position>(e).y, 2.0f);
  EXPECT_EQ(registry.tryGet<Position>(e), &registry.get<Position>(e));
  EXPECT_EQ(registry.size<Position>(), 1u);

  EXPECT_TRUE(registry.remove<Position>(e));
  EXPECT_FALSE(registry.remove<Position>(e));
  EXPECT_FALSE(registry.has<Position>(e));
  EXPECT_TRUE(registry.valid(e));  // removing a component keeps the entity
  EXPECT_EQ(registry.size<Position>(), 0u);
}

// Tricky: the error must leave the first component untouched (no partial replace).
TEST(Registry, DuplicateEmplaceThrowsAndKeepsTheOriginal) {
  Registry registry;
  const Entity e = registry.create();
  registry.emplace<std::string>(e, "first");
  try {
    registry.emplace<std::string>(e, "second");
    FAIL() << "duplicate emplace did not throw";
  } catch (const std::logic_error& error) {
    EXPECT_NE(std::string(error.what()).find("already has"), std::string::npos) << error.what();
    EXPECT_NE(std::string(error.what()).find("string"), std::string::npos) << "names the type: " << error.what();
  }
  EXPECT_EQ(registry.get<std::string>(e), "first");
  EXPECT_EQ(registry.size<std::string>(), 1u);
}

// Tricky: replacing from an argument that aliases the component being replaced.
TEST(Registry, EmplaceOrReplaceOverwritesEvenFromItself) {
  Registry registry;
  const Entity e = registry.create();
  registry.emplaceOrReplace<std::string>(e, "one");
  EXPECT_EQ(registry.get<std::string>(e), "one");
  registry.emplaceOrReplace<std::string>(e, registry.get<std::string>(e) + " two");
  EXPECT_EQ(registry.get<std::string>(e), "one two");
  const std::string& self = registry.get<std::string>(e);
  registry.emplaceOrReplace<std::string>(e, self);
  EXPECT_EQ(registry.get<std::string>(e), "one two");
  EXPECT_EQ(registry.size<std::string>(), 1u);
}

TEST(Registry, GetOfMissingComponentThrowsNamingTheProblem) {
  Registry registry;
  const Entity e = registry.create();
  registry.emplace<int>(e, 1);
  try {
    (void)registry.get<Position>(e);
    FAIL() << "get of a missing component did not throw";
  } catch (const std::logic_error& error) {
    EXPECT_NE(std::string(error.what()).find("Position"), std::string::npos) << error.what();
  }
  registry.destroy(e);
  try {
    (void)registry.get<int>(e);
    FAIL() << "get on a dead entity did not throw";
  } catch (const std::logic_error& error) {
    EXPECT_NE(std::string(error.what()).find("not alive"), std::string::npos) << error.what();
  }
}

// Tricky: swap-and-pop moves the last component into the hole; it must stay attached to its own
// entity, and removing the last element itself must not corrupt anything.
TEST(Registry, RemovalKeepsOtherEntitiesComponents) {
  Registry registry;
  std::vector<Entity> entities;
  for (int i = 0; i < 6; ++i) {
    entities.push_back(registry.create());
    registry.emplace<int>(entities.back(), i * 10);
  }
  registry.remove<int>(entities[1]);  // middle: last (50) moves here
  registry.remove<int>(entities[5]);  // now somewhere in the middle, not last
  registry.remove<int>(entities[3]);
  const std::vector<int> expected = {0, -1, 20, -1, 40, -1};
  for (std::size_t i = 0; i < entities.size(); ++i) {
    const int* value = registry.tryGet<int>(entities[i]);
    if (expected[i] < 0) {
      EXPECT_EQ(value, nullptr) << i;
    } else {
      ASSERT_NE(value, nullptr) << i;
      EXPECT_EQ(*value, expected[i]) << i;
    }
  }
  EXPECT_EQ(registry.size<int>(), 3u);
}

// Tricky: destroy must reach every storage the entity is in, and only that entity's components.
TEST(Registry, DestroyRemovesAllItsComponentsAndRunsDestructors) {
  Tracked::live = 0;
  {
    Registry registry;
    const Entity a = registry.create();
    const Entity b = registry.create();
    registry.emplace<Tracked>(a, 1);
    registry.emplace<Tracked>(b, 2);
    registry.emplace<Position>(a);
    registry.emplace<std::string>(a, std::string(100, 'a'));
    EXPECT_EQ(Tracked::live, 2);

    registry.destroy(a);
    EXPECT_EQ(Tracked::live, 1);
    EXPECT_EQ(registry.size<Tracked>(), 1u);
    EXPECT_EQ(registry.size<Position>(), 0u);
    EXPECT_EQ(registry.size<std::string>(), 0u);
    EXPECT_EQ(registry.get<Tracked>(b).value, 2);
  }
  EXPECT_EQ(Tracked::live, 0) << "registry destructor must destroy the remaining components";
}

// Tricky: move-only components must survive swap-and-pop (moved, not copied) without leaking.
TEST(Registry, MoveOnlyComponentsSurviveSwapAndPop) {
  Registry registry;
  std::vector<Entity> entities;
  for (int i = 0; i < 100; ++i) {
    entities.push_back(registry.create());
    registry.emplace<std::unique_ptr<int>>(entities.back(), std::make_unique<int>(i));
  }
  for (int i = 0; i < 100; i += 3) registry.remove<std::unique_ptr<int>>(entities[static_cast<std::size_t>(i)]);
  for (int i = 0; i < 100; ++i) {
    const auto* pointer = registry.tryGet<std::unique_ptr<int>>(entities[static_cast<std::size_t>(i)]);
    if (i % 3 == 0) {
      EXPECT_EQ(pointer, nullptr);
    } else {
      ASSERT_NE(pointer, nullptr);
      ASSERT_NE(*pointer, nullptr);
      EXPECT_EQ(**pointer, i);
    }
  }
}

// Tricky: emplacing thousands more components would reallocate a plain vector and leave the
// reference dangling; the paged storage must keep the same object in place.
TEST(Registry, ComponentReferencesSurviveLaterEmplaces) {
  Registry registry;
  const Entity first = registry.create();
  std::string& firstName = registry.emplace<std::string>(first, "first component, longer than SSO capacity");
  const std::string* address = &firstName;
  for (int i = 0; i < 20000; ++i) registry.emplace<std::string>(registry.create(), std::to_string(i));
  EXPECT_EQ(&registry.get<std::string>(first), address);
  EXPECT_EQ(firstName, "first component, longer than SSO capacity");
  // Copying one component into a new one while the storage grows must read a live source.
  for (int i = 0; i < 5000; ++i) registry.emplace<std::string>(registry.create(), registry.get<std::string>(first));
  EXPECT_EQ(registry.size<std::string>(), 25001u);
}

// Tricky: clear must invalidate every old handle (generation bump) while leaving the registry usable.
TEST(Registry, ClearDestroysEverythingAndInvalidatesHandles) {
  Tracked::live = 0;
  Registry registry;
  std::vector<Entity> entities;
  for (int i = 0; i < 10; ++i) {
    entities.push_back(registry.create());
    registry.emplace<Tracked>(entities.back(), i);
  }
  registry.clear();
  EXPECT_EQ(registry.alive(), 0u);
  EXPECT_EQ(registry.size<Tracked>(), 0u);
  EXPECT_EQ(Tracked::live, 0);
  for (const Entity e : entities) EXPECT_FALSE(registry.valid(e));

  const Entity fresh = registry.create();
  EXPECT_TRUE(registry.valid(fresh));
  EXPECT_EQ(registry.indexBound(), 10u) << "indices are reused after clear, not grown";
  for (const Entity e : entities) EXPECT_NE(e, fresh);
  registry.emplace<Tracked>(fresh, 99);
  EXPECT_EQ(registry.get<Tracked>(fresh).value, 99);
  EXPECT_EQ(Tracked::live, 1);
}

// Tricky: the const overloads must compile against a const registry and return const access.
TEST(Registry, ConstRegistryReadsComponents) {
  Registry registry;
  const Entity e = registry.create();
  registry.emplace<Position>(e, 4.0f, 5.0f);
  const Registry& reader = registry;
  static_assert(std::is_same_v<decltype(reader.get<Position>(e)), const Position&>);
  static_assert(std::is_same_v<decltype(reader.tryGet<Position>(e)), const Position*>);
  EXPECT_EQ(reader.get<Position>(e).y, 5.0f);
  EXPECT_EQ(reader.tryGet<int>(e), nullptr);  // type never stored: no storage, no crash
  EXPECT_TRUE(reader.has<Position>(e));
  EXPECT_EQ(reader.size<Position>(), 1u);
}

TEST(Entity, ComparesHashesAndFormats) {
  const Entity a{3, 1};
  const Entity b{3, 2};
  const Entity c{4, 1};
  EXPECT_NE(a, b);
  EXPECT_LT(a, b);  // same index: ordered by generation
  EXPECT_EQ(Entity::fromBits(b.bits()), b);
  const std::unordered_set<Entity> set = {a, b, c, a};
  EXPECT_EQ(set.size(), 3u);
  EXPECT_EQ(fmt::format("{}", a), "3:1");
  EXPECT_EQ(fmt::format("{}", kNullEntity), "null");
}

}  // namespace
}  // namespace engine::ecs
