// The fixture of the core robustness tests (malformed_cloud_test.cpp, degenerate_cloud_test.cpp):
// a good frame to warm a pipeline with, and a good frame after anything, whose result must be a
// fresh pipeline's.
#pragma once

#include <gtest/gtest.h>

#include <cstdio>
#include <string>

#include "expectations.hpp"
#include "synthetic_cloud.hpp"

namespace ring_curvature
{
namespace test
{

class Malformed : public ::testing::Test
{
protected:
  static void SetUpTestSuite()
  {
    warm_ = new Cloud(goodCloud(16, 900));
    next_ = new Cloud(goodCloud(32, 1024));
    next_ref_ = new FrameResult;
    Pipeline fresh;
    const Status st = fresh.process(next_->view(), *next_ref_);
    ASSERT_TRUE(st.ok) << st.message;
  }
  static void TearDownTestSuite()
  {
    delete warm_;
    delete next_;
    delete next_ref_;
  }

  /// Warms a pipeline on a good frame, feeds `bad`, then checks the next good frame.
  /// Returns the rejection message ("" if the frame was wrongly accepted).
  std::string rejectAndRecover(const PointCloudView& bad, const Params& params = {})
  {
    Pipeline pipeline(params);
    FrameResult r;
    Status st = pipeline.process(warm_->view(), r);
    EXPECT_TRUE(st.ok) << st.message;
    st = pipeline.process(bad, r);
    EXPECT_FALSE(st.ok) << "malformed frame accepted";
    EXPECT_FALSE(st.message.empty()) << "rejection without a message";
    expectEmpty(r);
    const std::string message = st.ok ? std::string() : st.message;
    std::printf("rejected: %s\n", message.c_str());  // the catalogue docs/robustness.md quotes
    recover(pipeline);
    return message;
  }

  /// The next good frame after anything comes out as from a fresh pipeline.
  void recover(Pipeline& pipeline)
  {
    FrameResult r;
    const Status st = pipeline.process(next_->view(), r);
    ASSERT_TRUE(st.ok) << st.message;
    expectSameResult(r, *next_ref_);
  }

  inline static Cloud* warm_ = nullptr;
  inline static Cloud* next_ = nullptr;
  inline static FrameResult* next_ref_ = nullptr;
};

}  // namespace test
}  // namespace ring_curvature
