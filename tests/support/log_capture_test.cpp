// The log capture the tests share (log_capture.h): a test asserting "said once" must see its level
// only, and must leave the log as it found it whichever way it ends.
#include <gtest/gtest.h>

#include <string>
#include <thread>
#include <vector>

#include "log_capture.h"

namespace {

using engine::log::Level;

// Tricky: a capture of warnings that also took errors (or infos) would let "warned once" pass on
// an error said once.
TEST(LogCapture, TakesItsLevelOnly) {
  hsdftest::LogCapture warnings;
  engine::log::info("an info");
  engine::log::warn("a warning about {}", "cells");
  engine::log::error("an error");
  engine::log::warn("another warning");
  EXPECT_EQ(warnings.messages(), (std::vector<std::string>{"a warning about cells", "another warning"}));
  EXPECT_EQ(warnings.count("warning"), 2u);
  EXPECT_EQ(warnings.count("cells"), 1u);
  EXPECT_EQ(warnings.count("error"), 0u);
}

TEST(LogCapture, ErrorsWhenAskedFor) {
  hsdftest::LogCapture errors(Level::Error);
  engine::log::warn("a warning");
  engine::log::error("an error naming 'broken'");
  EXPECT_EQ(errors.messages(), std::vector<std::string>{"an error naming 'broken'"});
}

// Tricky: the capture's sink refers to the capture; once it is gone the log must write to stderr
// again, not into freed memory (what a hand-written capture did after a failed ASSERT).
TEST(LogCapture, TheDefaultSinkIsBackAfterItsScope) {
  { hsdftest::LogCapture warnings; }
  testing::internal::CaptureStderr();
  engine::log::warn("said after the capture");
  const std::string written = testing::internal::GetCapturedStderr();
  EXPECT_NE(written.find("[warning] said after the capture"), std::string::npos) << written;
}

// Workers log too (the bake job's threads): every message arrives, none torn.
TEST(LogCapture, MessagesFromSeveralThreads) {
  hsdftest::LogCapture warnings;
  std::vector<std::thread> threads;
  for (int t = 0; t < 4; ++t)
    threads.emplace_back([t] {
      for (int i = 0; i < 100; ++i) engine::log::warn("thread {} message {}", t, i);
    });
  for (std::thread& thread : threads) thread.join();
  EXPECT_EQ(warnings.messages().size(), 400u);
  EXPECT_EQ(warnings.count("thread 3 "), 100u);
}

}  // namespace
