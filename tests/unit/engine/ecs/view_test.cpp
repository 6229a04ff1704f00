// Views: membership over 1-3 component types, driver choice, const access, and the snapshot
// guarantees when the registry changes during iteration.
#include <algorithm>
#include <map>
#include <random>
#include <set>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <vector>

#include <gtest/gtest.h>

#include "engine/ecs/registry.h"

namespace engine::ecs {
namespace {

struct A {
  int value = 0;
};
struct B {
  int value = 0;
};
struct C {
  std::string value;
};

std::set<Entity> collectEach(const View<A>& view) {
  std::set<Entity> seen;
  view.each([&](Entity e, const A&) { seen.insert(e); });
  return seen;
}

template <class ViewType>
std::set<Entity> collectRange(const ViewType& view) {
  return std::set<Entity>(view.begin(), view.end());
}

// Tricky: every combination of membership (including entities with none and with all) so an
// intersection that forgot a storage, or used the wrong one, shows up.
TEST(View, VisitsExactlyTheEntitiesWithAllComponents) {
  Registry registry;
  std::set<Entity> withA;
  std::set<Entity> withAB;
  std::set<Entity> withABC;
  for (int i = 0; i < 64; ++i) {
    const Entity e = registry.create();
    const int mask = i % 8;
    if (mask & 1) registry.emplace<A>(e, i);
    if (mask & 2) registry.emplace<B>(e, i);
    if (mask & 4) registry.emplace<C>(e, std::to_string(i));
    if (mask & 1) withA.insert(e);
    if ((mask & 3) == 3) withAB.insert(e);
    if (mask == 7) withABC.insert(e);
  }
  EXPECT_EQ(collectEach(registry.view<A>()), withA);
  EXPECT_EQ(collectRange(registry.view<A>()), withA);
  EXPECT_EQ(collectRange(registry.view<A, B>()), withAB);
  EXPECT_EQ(collectRange(registry.view<B, A>()), withAB);
  EXPECT_EQ(collectRange(registry.view<A, B, C>()), withABC);
  EXPECT_EQ(collectRange(registry.view<C, B, A>()), withABC);

  int visits = 0;
  registry.view<A, B, C>().each([&](Entity e, A& a, B& b, C& c) {
    ++visits;
    EXPECT_EQ(a.value, b.value);  // each argument is this entity's own component
    EXPECT_EQ(std::to_string(a.value), c.value);
    EXPECT_EQ(&a, &registry.get<A>(e));
  });
  EXPECT_EQ(visits, static_cast<int>(withABC.size()));

  int withoutEntityArgument = 0;
  registry.view<A, B>().each([&](A& a, B&) {
    a.value += 1000;
    ++withoutEntityArgument;
  });
  EXPECT_EQ(withoutEntityArgument, static_cast<int>(withAB.size()));
  for (const Entity e : withAB) EXPECT_GE(registry.get<A>(e).value, 1000) << "each wrote through the reference";
}

// Tricky: the driver choice is only observable through the order, so A and B are filled in opposite
// orders and whichever storage is smaller must dictate the visiting order.
TEST(View, IsDrivenByTheSmallestStorage) {
  Registry registry;
  std::vector<Entity> entities;
  for (int i = 0; i < 10; ++i) entities.push_back(registry.create());
  for (const Entity e : entities) registry.emplace<A>(e);
  std::vector<Entity> bOrder;
  for (auto it = entities.rbegin(); it != entities.rend(); ++it) {
    if (it->index % 2 == 0) {
      registry.emplace<B>(*it);
      bOrder.push_back(*it);
    }
  }
  // B (5 entities) is smaller than A (10): visit in B's order, whatever the template order.
  const auto viewAB = registry.view<A, B>();
  EXPECT_EQ(std::vector<Entity>(viewAB.begin(), viewAB.end()), bOrder);
  const auto viewBA = registry.view<B, A>();
  EXPECT_EQ(std::vector<Entity>(viewBA.begin(), viewBA.end()), bOrder);

  // Make A the smaller one: now A's (creation) order drives.
  for (std::size_t i = 6; i < entities.size(); ++i) registry.remove<A>(entities[i]);
  for (std::size_t i = 0; i < 6; ++i) {
    if (entities[i].index % 2 == 1) registry.emplace<B>(entities[i]);
  }
  ASSERT_LT(registry.size<A>(), registry.size<B>());
  const auto smallerA = registry.view<A, B>();
  EXPECT_EQ(std::vector<Entity>(smallerA.begin(), smallerA.end()),
            std::vector<Entity>(entities.begin(), entities.begin() + 6));
}

TEST(View, GetReturnsTheEntitysComponentAndThrowsForNonMembers) {
  Registry registry;
  const Entity both = registry.create();
  const Entity onlyA = registry.create();
  registry.emplace<A>(both, 1);
  registry.emplace<B>(both, 2);
  registry.emplace<A>(onlyA, 3);
  const auto view = registry.view<A, B>();
  EXPECT_EQ(view.get<B>(both).value, 2);
  view.get<A>(both).value = 10;
  EXPECT_EQ(registry.get<A>(both).value, 10);
  EXPECT_TRUE(view.contains(both));
  EXPECT_FALSE(view.contains(onlyA));
  EXPECT_THROW(view.get<B>(onlyA), std::logic_error);
}

// Tricky: a const registry cannot create storages, so a type never emplaced must give an empty
// view instead of dereferencing a missing storage; and components must come out const.
TEST(View, ConstRegistryGivesConstComponentsAndHandlesMissingTypes) {
  Registry registry;
  const Entity e = registry.create();
  registry.emplace<A>(e, 5);
  const Registry& reader = registry;

  int visits = 0;
  reader.view<A>().each([&](Entity, auto& a) {
    static_assert(std::is_const_v<std::remove_reference_t<decltype(a)>>);
    EXPECT_EQ(a.value, 5);
    ++visits;
  });
  EXPECT_EQ(visits, 1);
  const auto constView = reader.view<A>();
  static_assert(std::is_same_v<decltype(constView.get<A>(e)), const A&>);

  const auto missing = reader.view<A, C>();  // C was never emplaced anywhere in this registry
  EXPECT_EQ(missing.begin(), missing.end());
  missing.each([&](Entity, const A&, const C&) { ADD_FAILURE() << "visited an entity of an empty view"; });
  EXPECT_FALSE(missing.contains(e));
}

// Tricky: destroying the entity being visited shifts the packed arrays (swap-and-pop); no entity may
// be skipped or visited twice.
TEST(View, DestroyingTheCurrentEntityVisitsEveryOtherOnce) {
  Registry registry;
  for (int i = 0; i < 100; ++i) registry.emplace<A>(registry.create(), i);
  std::multiset<int> visited;
  registry.view<A>().each([&](Entity e, A& a) {
    visited.insert(a.value);
    registry.destroy(e);
  });
  EXPECT_EQ(visited.size(), 100u);
  EXPECT_EQ(std::set<int>(visited.begin(), visited.end()).size(), 100u) << "an entity was visited twice";
  EXPECT_EQ(registry.size<A>(), 0u);
}

// Tricky: same as above through range-for, removing a component rather than destroying.
TEST(View, RemovingTheCurrentComponentInRangeForVisitsEveryOtherOnce) {
  Registry registry;
  for (int i = 0; i < 100; ++i) {
    const Entity e = registry.create();
    registry.emplace<A>(e, i);
    registry.emplace<B>(e, i);
  }
  std::set<Entity> visited;
  for (const Entity e : registry.view<A, B>()) {
    EXPECT_TRUE(visited.insert(e).second) << "visited twice";
    registry.remove<B>(e);
  }
  EXPECT_EQ(visited.size(), 100u);
  EXPECT_EQ(registry.size<B>(), 0u);
}

// Tricky: an entity destroyed by the callback before its turn must not be visited, and the entity
// that swap-and-pop moves into its slot must still be visited exactly once.
TEST(View, EntitiesDestroyedBeforeTheirTurnAreSkipped) {
  Registry registry;
  std::vector<Entity> entities;
  for (int i = 0; i < 20; ++i) {
    entities.push_back(registry.create());
    registry.emplace<A>(entities.back(), i);
  }
  const auto view = registry.view<A>();
  const std::vector<Entity> order(view.begin(), view.end());
  std::vector<Entity> visited;
  view.each([&](Entity e, A&) {
    visited.push_back(e);
    if (e == order.front()) {
      registry.destroy(order[5]);
      registry.destroy(order[10]);
    }
  });
  std::vector<Entity> expected = order;
  expected.erase(expected.begin() + 10);
  expected.erase(expected.begin() + 5);
  EXPECT_EQ(visited, expected);
}

// Tricky: emplacing during iteration both grows the iterated storage (new entities must not be
// visited, which would also loop forever here) and would reallocate a plain array under the
// reference the callback still holds.
TEST(View, EmplacingDuringIterationIsSafeAndNewEntitiesAreNotVisited) {
  Registry registry;
  for (int i = 0; i < 10; ++i) registry.emplace<A>(registry.create(), i);
  int visits = 0;
  registry.view<A>().each([&](Entity, A& a) {
    ++visits;
    for (int k = 0; k < 1000; ++k) registry.emplace<A>(registry.create(), -1);
    a.value += 100;  // `a` must still be this entity's component after the storage grew
  });
  EXPECT_EQ(visits, 10);
  EXPECT_EQ(registry.size<A>(), 10u + 10u * 1000u);
  int updated = 0;
  registry.view<A>().each([&](const A& a) { updated += a.value >= 100 ? 1 : 0; });
  EXPECT_EQ(updated, 10);
}

// Tricky: an entity that joins the view by gaining the non-driving component mid-loop must not
// be visited (snapshot rule), even if it sits before the cursor in the driving storage.
TEST(View, EntitiesJoiningDuringIterationAreNotVisited) {
  Registry registry;
  std::vector<Entity> entities;
  for (int i = 0; i < 10; ++i) {
    entities.push_back(registry.create());
    registry.emplace<A>(entities.back(), i);
  }
  for (int i = 0; i < 3; ++i) registry.emplace<B>(entities[static_cast<std::size_t>(i)]);
  std::set<Entity> visited;
  registry.view<A, B>().each([&](Entity e, A&, B&) {
    visited.insert(e);
    for (const Entity other : entities) {
      if (!registry.has<B>(other)) registry.emplace<B>(other);
    }
  });
  EXPECT_EQ(visited, std::set<Entity>(entities.begin(), entities.begin() + 3));
  EXPECT_EQ(collectRange(registry.view<A, B>()).size(), 10u) << "a new view sees them";
}

// Model-based: random changes of the iterated storages inside the loop. The visited sequence must be
// exactly the recorded order filtered by membership at the moment each entity's turn comes, which the
// test decides from its own model, not from the registry. Tricky because destroys, removals,
// re-adds and index reuse all interleave with the cursor.
TEST(View, RandomChangesDuringIterationFollowTheSnapshotRule) {
  std::mt19937 random(1234);
  for (int round = 0; round < 20; ++round) {
    Registry registry;
    std::map<Entity, std::pair<bool, bool>> model;  // alive entity -> (has A, has B)
    for (int i = 0; i < 300; ++i) {
      const Entity e = registry.create();
      const bool hasA = random() % 3 != 0;
      const bool hasB = random() % 2 != 0;
      if (hasA) registry.emplace<A>(e);
      if (hasB) registry.emplace<B>(e);
      model[e] = {hasA, hasB};
    }
    const auto inView = [&](Entity e) {
      const auto it = model.find(e);
      return it != model.end() && it->second.first && it->second.second;
    };
    const auto view = registry.view<A, B>();
    const std::vector<Entity> order(view.begin(), view.end());
    std::size_t cursor = 0;  // next position in `order` that may be visited

    view.each([&](Entity e, A&, B&) {
      while (cursor < order.size() && order[cursor] != e) {
        EXPECT_FALSE(inView(order[cursor])) << "skipped an entity still in the view";
        ++cursor;
      }
      ASSERT_LT(cursor, order.size()) << "visited an entity not in the record, or out of order";
      EXPECT_TRUE(inView(e));
      ++cursor;
      for (int change = 0; change < 3; ++change) {
        auto it = model.begin();
        std::advance(it, static_cast<long>(random() % model.size()));
        const Entity target = it->first;
        switch (random() % 5) {
          case 0:
            registry.destroy(target);
            model.erase(it);
            break;
          case 1:
            if (registry.remove<A>(target)) it->second.first = false;
            break;
          case 2:
            if (registry.remove<B>(target)) it->second.second = false;
            break;
          case 3:
            if (!it->second.first) registry.emplace<A>(target);
            it->second.first = true;
            break;
          default: {
            const Entity fresh = registry.create();  // may reuse a destroyed index
            registry.emplace<A>(fresh);
            registry.emplace<B>(fresh);
            model[fresh] = {true, true};
          }
        }
        if (model.empty()) model[registry.create()] = {false, false};
      }
    });
    for (; cursor < order.size(); ++cursor) EXPECT_FALSE(inView(order[cursor])) << "never visited";
  }
}

}  // namespace
}  // namespace engine::ecs
