#include "ring_curvature/pipeline.hpp"

#include <array>
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
  // Raw pointers: a label is a byte, and a byte store may alias anything, so through the vectors
  // the compiler reloaded every data pointer after each label store (perf).
  const std::size_t m = grid_.size();
  const std::uint32_t* const index = grid_.index.data();
  const Label* const lab = labels_.data();
  const float* const curv = features_.curvature.data();
  const float* const smooth = features_.smoothness.data();
  const float* const disc = features_.discontinuity.data();
  const std::int32_t* const prim = out.primitives.of_grid.data();
  std::uint8_t* const out_label = out.label.data();
  float* const out_curv = out.curvature.data();
  float* const out_smooth = out.smoothness.data();
  float* const out_disc = out.discontinuity.data();
  std::int32_t* const out_prim = out.primitive.data();
  std::array<std::size_t, kNumLabels> counts{};
  auto put = [&](std::size_t i, std::size_t p) {
    const auto l = static_cast<std::uint8_t>(lab[p]);
    out_label[i] = l;
    out_curv[i] = curv[p];
    out_smooth[i] = smooth[p];
    out_disc[i] = disc[p];
    out_prim[i] = prim[p];
    ++counts[l];
  };
  for (std::size_t p = 0; p < m; ++p) put(index[p], p);
  for (const std::uint32_t i : grid_.duplicates) put(i, static_cast<std::size_t>(grid_.grid_pos[i]));
  for (std::size_t l = 0; l < counts.size(); ++l) out.label_counts[l] += counts[l];
  // everything else (invalid returns, second returns) is None
  out.label_counts[static_cast<std::size_t>(Label::None)] += n - m - grid_.duplicates.size();
  out.times.output = msSince(t);
  return Status::success();
}

}  // namespace ring_curvature
