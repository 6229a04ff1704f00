// Pipelines described now and compiled when first used (engine/gpu/lazy_pipeline.h). What is
// compiled, and when, is observed through the shader statistics of RADV's null NAVI10 device
// (engine/gpu/shader_statistics.h): every pipeline created through engine::gpu::Pipeline is
// compiled there again and leaves rows named after it, so a row says "this was compiled" without
// any hook in the code under test.
#include <gtest/gtest.h>

#include <algorithm>
#include <memory>
#include <string>
#include <thread>
#include <vector>

#include "engine/gpu/context.h"
#include "engine/gpu/lazy_pipeline.h"
#include "engine/gpu/shader_statistics.h"
#include "engine/gpu/vk_check.h"
#include "mesh_prepass_pipeline.h"
#include "test_files.h"
#include "test_device.h"

namespace engine::gpu {
namespace {

class LazyPipelineTest : public ::testing::Test {
 protected:
  // RADV shows its null device only when the variable is set as the instance is created.
  hsdftest::ScopedEnvironment family_{"RADV_FORCE_FAMILY", "navi10"};

  void SetUp() override {
    ContextDesc desc;
    desc.applicationName = "lazy pipeline test";
    const auto device = hsdftest::testDevicePreference();
    ASSERT_TRUE(device.ok()) << device.error().message;
    desc.device = *device;
    desc.validation = true;
    desc.shaderStatistics = {StatisticsTarget::Device, "NAVI10"};
    auto context = Context::create(desc);
    ASSERT_TRUE(context.ok()) << "RADV's null NAVI10 device (mesa-vulkan-drivers) is needed: " << context.error().message;
    context_ = std::move(*context);
  }
  void TearDown() override {
    clearInjectedFaults();
    if (context_) {
      EXPECT_EQ(hsdftest::messagesThroughDestruction(context_), 0u);
    }
  }

  // mesh.vert with mesh_prepass.frag (an id target and depth), named `name`. The test's own
  // references to the modules end here: only the LazyPipeline keeps them.
  LazyPipeline describe(const std::string& name) { return describeMeshPrepass(*context_, name); }

  // How many times the pipeline `name` was compiled (its vertex stage's rows).
  std::size_t compiled(const std::string& name) const {
    const std::vector<StageStatistics> rows = context_->shaderStatistics()->stages();
    return std::size_t(std::count_if(rows.begin(), rows.end(), [&](const StageStatistics& row) {
      return row.pipeline == name && row.stage == "vertex";
    }));
  }

  std::unique_ptr<Context> context_;
};

// Tricky: describing must compile nothing, the first use must compile exactly once, and the shader
// modules must outlive the caller's references to them: a pipeline compiled from destroyed modules
// is a validation error, which fails the test in TearDown.
TEST_F(LazyPipelineTest, CompiledOnFirstUseAndOnlyOnce) {
  LazyPipeline pipeline = describe("first use");
  ASSERT_TRUE(pipeline.described());
  EXPECT_FALSE(pipeline.made());
  EXPECT_EQ(compiled("first use"), 0u) << "describing compiles nothing";
  const auto first = pipeline.get(*context_);
  ASSERT_TRUE(first.ok()) << first.error().message;
  ASSERT_NE(*first, nullptr);
  EXPECT_NE((*first)->handle(), VkPipeline(VK_NULL_HANDLE));
  EXPECT_TRUE(pipeline.made());
  EXPECT_EQ(compiled("first use"), 1u);
  const auto again = pipeline.get(*context_);
  ASSERT_TRUE(again.ok());
  EXPECT_EQ(*again, *first) << "the same pipeline";
  EXPECT_EQ(pipeline.getOrLog(*context_), *first);
  EXPECT_EQ(compiled("first use"), 1u) << "not compiled again";
}

// Tricky: a failed compile would otherwise be retried by every frame that draws with the pipeline
// (and logged every frame); the failure is kept until the owner describes the pipeline again.
// The fault fires once, so a retry would succeed and show here.
TEST_F(LazyPipelineTest, AFailureIsKeptAndNotRetried) {
  LazyPipeline pipeline = describe("fails");
  injectFault({"vkCreateGraphicsPipelines", VK_ERROR_OUT_OF_HOST_MEMORY, 0});
  const auto failed = pipeline.get(*context_);
  ASSERT_FALSE(failed.ok());
  EXPECT_NE(failed.error().message.find("vkCreateGraphicsPipelines"), std::string::npos) << failed.error().message;
  clearInjectedFaults();
  const auto again = pipeline.get(*context_);
  ASSERT_FALSE(again.ok()) << "retried";
  EXPECT_EQ(again.error().message, failed.error().message);
  EXPECT_EQ(pipeline.getOrLog(*context_), nullptr);
  EXPECT_FALSE(pipeline.made());
  EXPECT_EQ(compiled("fails"), 0u);

  LazyPipeline never;
  EXPECT_FALSE(never.described());
  const auto undescribed = never.get(*context_);
  ASSERT_FALSE(undescribed.ok());
  EXPECT_NE(undescribed.error().message.find("never described"), std::string::npos) << undescribed.error().message;
}

// Tricky: a reload pairs each fresh pipeline with the old one at the same position and compiles
// only those frames had bound; compiling the others would undo the point of describing them, and
// skipping a bound one would leave the next frame to find a broken shader mid-frame. One that was
// only warmed is made like a bound one but not needed: compiling it here would put the warmer's
// work back on the reloading frame. createAll() skips a slot nothing was described for (a variant
// a device does not have).
TEST_F(LazyPipelineTest, AReloadCompilesWhatFramesBoundAndCreateAllEveryDescribedOne) {
  LazyPipeline oldUsed = describe("old used"), oldUnused = describe("old unused"), oldWarmed = describe("old warmed");
  ASSERT_TRUE(oldUsed.get(*context_).ok());
  oldWarmed.warm(*context_);
  ASSERT_TRUE(oldWarmed.made());
  EXPECT_TRUE(oldUsed.needed());
  EXPECT_FALSE(oldWarmed.needed());
  LazyPipeline freshUsed = describe("fresh used"), freshUnused = describe("fresh unused"),
               freshWarmed = describe("fresh warmed");
  std::vector<LazyPipeline*> oldSet = {&oldUsed, &oldUnused, &oldWarmed};
  std::vector<LazyPipeline*> freshSet = {&freshUsed, &freshUnused, &freshWarmed};
  const Status reloaded = createWhereNeeded(*context_, freshSet, oldSet);
  ASSERT_TRUE(reloaded.ok()) << reloaded.error().message;
  EXPECT_TRUE(freshUsed.made());
  EXPECT_TRUE(freshUsed.needed()) << "a second reload must compile it again";
  EXPECT_FALSE(freshUnused.made());
  EXPECT_FALSE(freshWarmed.made());
  EXPECT_EQ(compiled("fresh used"), 1u);
  EXPECT_EQ(compiled("fresh unused"), 0u);
  EXPECT_EQ(compiled("fresh warmed"), 0u);
  const std::vector<LazyPipeline*> shorter = {&freshUsed};
  EXPECT_FALSE(createWhereNeeded(*context_, shorter, oldSet).ok()) << "sets of different sizes";

  LazyPipeline undescribed;
  std::vector<LazyPipeline*> all = {&freshUsed, &freshUnused, &undescribed};
  const Status created = createAll(*context_, all);
  ASSERT_TRUE(created.ok()) << created.error().message;
  EXPECT_TRUE(freshUnused.made());
  EXPECT_EQ(compiled("fresh used"), 1u) << "a compiled one is not compiled again";
  EXPECT_EQ(compiled("fresh unused"), 1u);
}

// Six described pipelines and the set of pointers a warmer takes.
struct Described {
  std::vector<LazyPipeline> pipelines;
  std::vector<LazyPipeline*> set() {
    std::vector<LazyPipeline*> out;
    for (LazyPipeline& pipeline : pipelines) out.push_back(&pipeline);
    return out;
  }
};

// Tricky: the point of warming is that the frame binds what the worker compiled: a pipeline the
// worker made must be found made, returned as is and not compiled again on the frame's thread.
TEST_F(LazyPipelineTest, AWarmedPipelineIsTheOneAFrameBinds) {
  Described d;
  for (int i = 0; i < 3; ++i) d.pipelines.push_back(describe("warmed " + std::to_string(i)));
  {
    PipelineWarmer warmer(*context_, d.set());
    warmer.wait();
    EXPECT_FALSE(warmer.running());
  }
  for (LazyPipeline& pipeline : d.pipelines) {
    ASSERT_TRUE(pipeline.made()) << pipeline.name();
    EXPECT_EQ(pipeline.compiles(), 1u);
    const auto bound = pipeline.get(*context_);
    ASSERT_TRUE(bound.ok());
    EXPECT_NE((*bound)->handle(), VkPipeline(VK_NULL_HANDLE));
    EXPECT_EQ(pipeline.compiles(), 1u) << pipeline.name() << " compiled again by the frame";
    EXPECT_EQ(compiled(pipeline.name()), 1u);
  }
}

// Tricky: the frame asks, on its own thread, for pipelines while the worker goes through the same
// set: the last ones before the worker reaches them (the frame compiles them; the worker must
// then skip them), the first ones while the worker compiles them (the frame must wait for that
// compile, not start its own). Either way each is compiled once and both threads see one handle.
TEST_F(LazyPipelineTest, AFrameNeedingAPipelineTheWorkerHasOrWillHaveGetsItCompiledOnce) {
  Described d;
  for (int i = 0; i < 6; ++i) d.pipelines.push_back(describe("shared " + std::to_string(i)));
  PipelineWarmer warmer(*context_, d.set());
  std::vector<VkPipeline> frame(d.pipelines.size());
  for (std::size_t k = d.pipelines.size(); k-- > 0;) {
    const auto bound = d.pipelines[k].get(*context_);
    ASSERT_TRUE(bound.ok()) << bound.error().message;
    frame[k] = (*bound)->handle();
  }
  warmer.wait();
  for (std::size_t k = 0; k < d.pipelines.size(); ++k) {
    EXPECT_EQ(d.pipelines[k].compiles(), 1u) << d.pipelines[k].name();
    EXPECT_EQ((*d.pipelines[k].get(*context_))->handle(), frame[k]);
  }
}

// Tricky: the owner goes (a feature destroyed, shaders reloaded) while its worker compiles; the
// warmer must stop before its next pipeline and be joined before the pipelines it points at are
// destroyed: a worker still running would compile into freed memory (the ASan build catches it) or
// compile after the context is gone (a validation message in TearDown).
TEST_F(LazyPipelineTest, DestroyingTheOwnerWhileItsWorkerRunsIsClean) {
  struct Owner {
    Described d;
    std::unique_ptr<PipelineWarmer> warmer;  // after the pipelines: destroyed first
  };
  auto owner = std::make_unique<Owner>();
  for (int i = 0; i < 8; ++i) owner->d.pipelines.push_back(describe("owned " + std::to_string(i)));
  owner->warmer = std::make_unique<PipelineWarmer>(*context_, owner->d.set());
  std::this_thread::yield();
  std::uint32_t made = 0;
  owner->warmer.reset();  // stop and join
  for (const LazyPipeline& pipeline : owner->d.pipelines) made += pipeline.made() ? 1u : 0u;
  EXPECT_LT(made, 8u) << "the worker went on after it was stopped";
  owner.reset();
  PipelineWarmer never;  // a warmer without a worker stops and waits at once
  never.wait();
  never.stop();
}

// Why: an owner's destructor may destroy what its pipelines' descriptions name (a descriptor set
// layout) before its members' destruction joins the warming's worker; it stops the warming first
// (PipelineWarming::stop), which must return with the worker stopped before its next pipeline and
// joined: nothing is compiled after it, and later frames start no other worker.
TEST_F(LazyPipelineTest, AStoppedWarmingCompilesNothingMore) {
  Described d;
  for (int i = 0; i < 8; ++i) d.pipelines.push_back(describe("stopped " + std::to_string(i)));
  std::uint32_t asked = 0;
  const PipelineWarming::NextSet next = [&] {
    ++asked;
    return d.set();
  };
  const auto madeCount = [&] {
    return std::uint32_t(std::count_if(d.pipelines.begin(), d.pipelines.end(),
                                       [](const LazyPipeline& pipeline) { return pipeline.made(); }));
  };
  PipelineWarming warming;
  warming.frame(*context_, true, next);
  warming.frame(*context_, true, next);
  ASSERT_TRUE(warming.started());
  warming.stop();
  const std::uint32_t made = madeCount();
  EXPECT_LT(made, 8u) << "the worker went on after it was stopped";
  warming.wait();
  warming.frame(*context_, true, next);
  EXPECT_EQ(madeCount(), made) << "a pipeline was compiled after stop() returned";
  EXPECT_EQ(asked, 1u) << "a frame after stop() started another worker";
  PipelineWarming neverStarted;
  neverStarted.stop();
  EXPECT_FALSE(neverStarted.started());
}

// Tricky: the warming's clock is the owner's frames, not time: the first frame that wants warming
// compiles its own pipelines and must not share the CPU with a worker, the second starts it; a
// reload stops the worker (it would compile into pipelines about to be replaced) and the very next
// frame warms the fresh set, since the reload compiled what that frame binds. A frame that does not
// want warming (setting off, nothing to draw) neither starts it nor counts.
TEST_F(LazyPipelineTest, WarmingStartsWithTheSecondFrameAndAgainRightAfterAReload) {
  Described d;
  for (int i = 0; i < 3; ++i) d.pipelines.push_back(describe("warming " + std::to_string(i)));
  std::uint32_t asked = 0;
  const PipelineWarming::NextSet next = [&] {
    ++asked;
    return d.set();
  };
  PipelineWarming warming;
  warming.frame(*context_, false, next);
  warming.frame(*context_, true, next);
  EXPECT_FALSE(warming.started()) << "the first frame that wants it compiles its own";
  warming.frame(*context_, false, next);
  EXPECT_FALSE(warming.started());
  warming.frame(*context_, true, next);
  ASSERT_TRUE(warming.started());
  warming.wait();
  for (const LazyPipeline& pipeline : d.pipelines) {
    EXPECT_TRUE(pipeline.made()) << pipeline.name();
    EXPECT_FALSE(pipeline.needed()) << pipeline.name() << ": warmed, not bound";
  }
  warming.frame(*context_, true, next);
  EXPECT_EQ(asked, 1u) << "warmed once per set";

  warming.reloading();
  EXPECT_FALSE(warming.started());
  for (int i = 0; i < 3; ++i) d.pipelines[std::size_t(i)] = describe("rewarmed " + std::to_string(i));
  warming.frame(*context_, true, next);
  ASSERT_TRUE(warming.started()) << "the frame after a reload warms the fresh set";
  warming.wait();
  EXPECT_EQ(asked, 2u);
  for (const LazyPipeline& pipeline : d.pipelines) EXPECT_EQ(compiled(pipeline.name()), 1u) << pipeline.name();

  PipelineWarming neverStarted;
  neverStarted.frame(*context_, true, next);
  neverStarted.reloading();
  neverStarted.frame(*context_, true, next);
  EXPECT_FALSE(neverStarted.started()) << "a reload before any warming: the frame after it is a first frame";
}

}  // namespace
}  // namespace engine::gpu
