// engine::gpu::DeferredRelease (engine/gpu/deferred_release.h): a retired object lives exactly until
// the frame that last used it has completed, i.e. until frame lastUse + framesInFlight is prepared.
#include <gtest/gtest.h>

#include <memory>
#include <vector>

#include "engine/gpu/deferred_release.h"

namespace engine::gpu {
namespace {

// Counts its own destructions (moved-from copies do not count), standing in for a GPU object.
struct Tracked {
  Tracked(std::vector<int>* destroyedLog, int objectId) : log(destroyedLog), id(objectId) {}
  Tracked(Tracked&& other) noexcept : log(other.log), id(other.id) { other.log = nullptr; }
  Tracked& operator=(Tracked&&) = delete;
  ~Tracked() {
    if (log) log->push_back(id);
  }
  std::vector<int>* log;
  int id;
};

// Tricky: with 2 frames in flight, an object last used by frame 5 must survive the preparation of
// frame 6 (frame 5 may still run) and go at frame 7, not earlier and not later; objects retired out
// of frame order go each at their own frame; a move-only owner (unique_ptr) is destroyed once.
TEST(DeferredRelease, DestroysEachObjectOnceItsFrameHasCompleted) {
  std::vector<int> destroyed;
  DeferredRelease release;
  release.retire(Tracked(&destroyed, 5), 5);
  release.retire(Tracked(&destroyed, 3), 3);
  release.retire(std::make_unique<Tracked>(&destroyed, 6), 6);
  EXPECT_TRUE(destroyed.empty()) << "retire() must not destroy";
  EXPECT_EQ(release.pending(), 3u);

  release.collect(4, 2);
  EXPECT_TRUE(destroyed.empty()) << "frame 3 may still run while frame 4 is prepared";
  release.collect(5, 2);
  EXPECT_EQ(destroyed, std::vector<int>({3}));
  release.collect(6, 2);
  EXPECT_EQ(destroyed, std::vector<int>({3}));
  release.collect(7, 2);
  EXPECT_EQ(destroyed, std::vector<int>({3, 5}));
  release.collect(8, 2);
  EXPECT_EQ(destroyed, std::vector<int>({3, 5, 6}));
  EXPECT_EQ(release.pending(), 0u);
}

// Tricky: the rule is the one the renderer's fences give (frame F waits for frame F - framesInFlight),
// including the first frames, where no earlier frame exists to underflow into.
TEST(DeferredRelease, CompletedFollowsTheFramesInFlight) {
  EXPECT_FALSE(DeferredRelease::completed(0, 0, 1));
  EXPECT_TRUE(DeferredRelease::completed(0, 1, 1));
  EXPECT_FALSE(DeferredRelease::completed(0, 2, 3));
  EXPECT_TRUE(DeferredRelease::completed(0, 3, 3));
  EXPECT_FALSE(DeferredRelease::completed(10, 12, 3));
  EXPECT_TRUE(DeferredRelease::completed(10, 13, 3));
}

// Tricky: objects still pending when the owner goes (the renderer waits for the device first) are
// destroyed with it, not leaked.
TEST(DeferredRelease, PendingObjectsGoWithTheOwner) {
  std::vector<int> destroyed;
  {
    DeferredRelease release;
    release.retire(Tracked(&destroyed, 1), 100);
    release.collect(50, 2);
    EXPECT_TRUE(destroyed.empty());
  }
  EXPECT_EQ(destroyed, std::vector<int>({1}));
}

}  // namespace
}  // namespace engine::gpu
