#include "ring_curvature/pipeline.hpp"

#include <chrono>
#include <limits>

namespace ring_curvature
{

namespace
{
using Clock = std::chrono::steady_clock;
double msSince(Clock::time_point& t)
{
  const auto now = Clock::now();
  const double ms = std::chrono::duration<double, std::milli>(now - t).count();
  t = now;
  return ms;
}
}  // namespace

Pipeline::Pipeline(const Params& params) : params_(params) {}

Status Pipeline::setParams(const Params& params)
{
  Status st = params.validate();
  if (st) params_ = params;
  return st;
}

Status Pipeline::process(const PointCloudView& view, FrameResult& out)
{
  out.times = StageTimes{};
  out.label_counts.fill(0);
  auto t = Clock::now();
  Status st = grid_builder_.build(view, params_, grid_);
  out.times.grid = msSince(t);
  if (!st)
  {
    out.label.clear();
    out.curvature.clear();
    out.smoothness.clear();
    out.discontinuity.clear();
    out.primitive.clear();
    out.primitives.clear();
    return st;
  }
  feature_computer_.compute(grid_, params_, features_);
  out.times.features = msSince(t);
  classifier_.computeThresholds(grid_, features_, params_, thresholds_);
  out.times.thresholds = msSince(t);
  classifier_.classify(grid_, features_, params_, thresholds_, labels_);
  out.times.classification = msSince(t);
  primitive_extractor_.extract(grid_, labels_, params_, out.primitives);
  out.times.primitives = msSince(t);

  // Scatter back to input order. Duplicates take their representative's results; invalid
  // returns and second returns stay unlabelled.
  const std::size_t n = grid_.num_input;
  constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();
  out.label.assign(n, static_cast<std::uint8_t>(Label::None));
  out.curvature.assign(n, kNaN);
  out.smoothness.assign(n, kNaN);
  out.discontinuity.assign(n, kNaN);
  out.primitive.assign(n, -1);
  // Walk the grid in order (sequential reads of five arrays) and write to each point's input
  // index, rather than walking the input and reading the grid at random through grid_pos.
  const std::size_t m = grid_.size();
  for (std::size_t p = 0; p < m; ++p)
  {
    const std::size_t i = grid_.index[p];
    const auto l = static_cast<std::uint8_t>(labels_[p]);
    out.label[i] = l;
    out.curvature[i] = features_.curvature[p];
    out.smoothness[i] = features_.smoothness[p];
    out.discontinuity[i] = features_.discontinuity[p];
    out.primitive[i] = out.primitives.of_grid[p];
    ++out.label_counts[l];
  }
  for (const std::uint32_t i : grid_.duplicates)
  {
    const auto p = static_cast<std::size_t>(grid_.grid_pos[i]);
    const auto l = static_cast<std::uint8_t>(labels_[p]);
    out.label[i] = l;
    out.curvature[i] = features_.curvature[p];
    out.smoothness[i] = features_.smoothness[p];
    out.discontinuity[i] = features_.discontinuity[p];
    out.primitive[i] = out.primitives.of_grid[p];
    ++out.label_counts[l];
  }
  // everything else (invalid returns, second returns) is None
  out.label_counts[static_cast<std::size_t>(Label::None)] += n - m - grid_.duplicates.size();
  out.times.output = msSince(t);
  return Status::success();
}

}  // namespace ring_curvature
