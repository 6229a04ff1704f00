// detail::runParallel (src/core/field/parallel.cpp): worker threads, progress and cancellation.
#include "field/parallel.h"

#include <gtest/gtest.h>

#include <atomic>
#include <vector>

namespace hsdf {
namespace {

// Tricky: the calling thread polls the callback every ~20 ms while the workers run, so work that
// finishes within the first poll used to complete without the callback ever being asked (a small
// sparse bake on a fast machine ignored a callback that refused at once; CI failed on it). A
// callback that refuses must stop the run before any item, whatever the work's length.
TEST(RunParallel, ACallbackThatRefusesAtOnceStopsBeforeAnyWork) {
  for (unsigned threads : {1u, 2u, 4u}) {
    std::atomic<int> ran{0};
    BakeOptions options;
    options.threads = threads;
    std::vector<float> fractions;
    options.progress = [&](float f) {
      fractions.push_back(f);
      return false;
    };
    const engine::Status status = detail::runParallel(64, options, [&](std::size_t) -> engine::Status {
      ++ran;
      return {};
    });
    ASSERT_FALSE(status.ok()) << threads << " threads";
    EXPECT_EQ(status.error().message, "cancelled");
    EXPECT_EQ(ran.load(), 0) << threads << " threads";
    ASSERT_EQ(fractions.size(), 1u);
    EXPECT_EQ(fractions.front(), 0.0f);
  }
}

// The callback sees the start (0) and the end (1), in order, for work too short for any poll.
TEST(RunParallel, ShortWorkReportsItsStartAndEnd) {
  std::atomic<int> ran{0};
  BakeOptions options;
  options.threads = 2;
  std::vector<float> fractions;
  options.progress = [&](float f) {
    fractions.push_back(f);
    return true;
  };
  ASSERT_TRUE(detail::runParallel(8, options, [&](std::size_t) -> engine::Status {
                ++ran;
                return {};
              }).ok());
  EXPECT_EQ(ran.load(), 8);
  ASSERT_GE(fractions.size(), 2u);
  EXPECT_EQ(fractions.front(), 0.0f);
  EXPECT_EQ(fractions.back(), 1.0f);
  for (std::size_t i = 1; i < fractions.size(); ++i) EXPECT_LE(fractions[i - 1], fractions[i]);
}

}  // namespace
}  // namespace hsdf
