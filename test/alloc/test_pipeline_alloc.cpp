// Issue 6: once its buffers are warm, the core makes no heap allocation per frame, whatever
// the order of frame sizes (a smaller frame after a larger one, organized after unorganized).
#include <gtest/gtest.h>

#include <functional>
#include <memory>
#include <vector>

#include "alloc_counter.hpp"
#include "ring_curvature/loam_features.hpp"
#include "ring_curvature/pipeline.hpp"
#include "synthetic_scene.hpp"

namespace rc = ring_curvature;
using rc::test::makeScene;
using rc::test::SceneOptions;
using rc::test::SyntheticFrame;

namespace
{

std::vector<SyntheticFrame> makeFrames()
{
  std::vector<SyntheticFrame> frames;
  SceneOptions a;  // VLP-16-like: 16 rings x 1800 firings, unorganized, ~28k points
  frames.push_back(makeScene(a));
  SceneOptions b = a;  // smaller: half the firings, boxes moved, other noise
  b.columns = 900;
  b.box_shift = 0.7f;
  b.seed = 2;
  frames.push_back(makeScene(b));
  SceneOptions c;  // Ouster-like organized 32 x 1024 with NaN misses
  c.rings = 32;
  c.columns = 1024;
  c.elevation_min_deg = -22.5f;
  c.elevation_max_deg = 22.5f;
  c.organized = true;
  c.seed = 3;
  frames.push_back(makeScene(c));
  SceneOptions d = a;  // dual return: every point twice (the primitives' duplicate counts)
  d.duplicate_every = 1;
  frames.push_back(makeScene(d));
  SceneOptions e = b;  // a few identical second returns
  e.duplicate_every = 40;
  frames.push_back(makeScene(e));
  return frames;
}

}  // namespace

TEST(AllocCounter, SeesAllocations)
{
  // The counter must be able to fail: a vector and a new must both be seen.
  if (!rc::test::allocCountingAvailable())
    GTEST_SKIP() << "malloc cannot be interposed in a sanitizer build";
  rc::test::startCountingAllocations();
  auto v = std::make_unique<std::vector<int>>(100);
  const std::size_t n = rc::test::stopCountingAllocations();
  EXPECT_GE(n, 2u);
  EXPECT_EQ(v->size(), 100u);
}

// Runs `process(i, warming)` on every frame once (the first must allocate: the counter sees the
// path's buffers grow), then twice over an order whose sizes go down as well as up (large, small,
// organized, small, large, large, dual, few duplicates), where no frame may allocate.
void expectNoneAfterWarmUp(std::size_t frames, const std::function<void(int, bool)>& process)
{
  for (std::size_t i = 0; i < frames; ++i)
  {
    if (i == 0) rc::test::startCountingAllocations();
    process(static_cast<int>(i), true);
    if (i == 0)
    {
      EXPECT_GT(rc::test::stopCountingAllocations(), 0u) << "the counter did not see the first frame's buffers grow";
    }
  }
  const int order[] = {0, 1, 2, 1, 0, 0, 2, 2, 1, 3, 4, 3, 0, 4, 1, 3, 2, 4};
  for (int pass = 0; pass < 2; ++pass)
    for (const int i : order)
    {
      rc::test::startCountingAllocations();
      process(i, false);
      const std::size_t n = rc::test::stopCountingAllocations();
      EXPECT_EQ(n, 0u) << "frame " << i << " allocated " << n << " times after warm-up (pass " << pass << ")";
    }
}

TEST(PipelineAllocations, NoneAfterWarmUp)
{
  if (!rc::test::allocCountingAvailable())
    GTEST_SKIP() << "malloc cannot be interposed in a sanitizer build";
  const std::vector<SyntheticFrame> frames = makeFrames();
  rc::Pipeline pipeline;
  rc::FrameResult result;
  expectNoneAfterWarmUp(frames.size(), [&](int i, bool warming) {
    const auto& f = frames[static_cast<std::size_t>(i)];
    const rc::Status st = pipeline.process(f.view, result);
    ASSERT_TRUE(st.ok) << st.message;
    ASSERT_GT(result.label_counts[static_cast<int>(rc::Label::Plane)], 0u) << "scene not processed";
    if (warming && i >= 3)  // the frames with duplicates have them
    {
      EXPECT_GT(pipeline.grid().duplicates.size() * (i == 3 ? 3 : 60), f.view.size()) << "frame " << i;
    }
  });
}

TEST(PipelineAllocations, NoneForTheLoamSetsAfterWarmUp)
{
  // The SLAM front end's path: labels on the grid only, then the LOAM sets and the degeneracy
  // report (the nodelet with only the ~loam/* outputs subscribed).
  if (!rc::test::allocCountingAvailable())
    GTEST_SKIP() << "malloc cannot be interposed in a sanitizer build";
  const std::vector<SyntheticFrame> frames = makeFrames();
  rc::Pipeline pipeline;
  rc::FrameResult result;
  rc::LoamFeatures loam;
  expectNoneAfterWarmUp(frames.size(), [&](int i, bool) {
    const auto& f = frames[static_cast<std::size_t>(i)];
    ASSERT_TRUE(pipeline.process(f.view, result, rc::Pipeline::Scope::GridLabels).ok);
    pipeline.selectLoamFeatures(f.view, loam);
    ASSERT_FALSE(loam.flat.empty()) << "frame " << i << ": no flat points chosen";
    ASSERT_FALSE(loam.less_sharp.empty()) << "frame " << i << ": no less sharp points chosen";
  });
}

TEST(PipelineAllocations, ResultIsTheFrameNotAStaleOne)
{
  // Reusing buffers must not leak the larger frame's data into the smaller one's result.
  const std::vector<SyntheticFrame> frames = makeFrames();
  rc::Pipeline pipeline;
  rc::FrameResult result;
  ASSERT_TRUE(pipeline.process(frames[0].view, result).ok);
  ASSERT_TRUE(pipeline.process(frames[1].view, result).ok);
  EXPECT_EQ(result.label.size(), frames[1].view.size());
  rc::FrameResult fresh;
  rc::Pipeline clean;
  ASSERT_TRUE(clean.process(frames[1].view, fresh).ok);
  EXPECT_EQ(result.label, fresh.label);
  EXPECT_EQ(result.primitives.primitives.size(), fresh.primitives.primitives.size());
}

int main(int argc, char** argv)
{
  testing::InitGoogleTest(&argc, argv);
  return RUN_ALL_TESTS();
}
