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
  // Walk the input in order and gather from the grid: the writes, five arrays, are sequential
  // and every entry is written once, while the reads follow the rings (a few streams per array,
  // cached). Filling the arrays first and then scattering in grid order wrote each entry
  // twice, with stores a cache line apart.
  // Raw pointers: a label is a byte, and a byte store may alias anything, so through the vectors
  // the compiler reloaded every data pointer after each label store (perf).
  const std::size_t n = grid_.num_input;
  constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();
  out.label.resize(n);
  out.curvature.resize(n);
  out.smoothness.resize(n);
  out.discontinuity.resize(n);
  out.primitive.resize(n);
  const PointState* const state = grid_.state.data();
  const std::int32_t* const grid_pos = grid_.grid_pos.data();
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
  for (std::size_t i = 0; i < n; ++i)
  {
    if (state[i] == PointState::OnGrid || state[i] == PointState::Duplicate)
    {
      const auto p = static_cast<std::size_t>(grid_pos[i]);
      out_label[i] = static_cast<std::uint8_t>(lab[p]);
      out_curv[i] = curv[p];
      out_smooth[i] = smooth[p];
      out_disc[i] = disc[p];
      out_prim[i] = prim[p];
    }
    else
    {
      out_label[i] = static_cast<std::uint8_t>(Label::None);
      out_curv[i] = kNaN;
      out_smooth[i] = kNaN;
      out_disc[i] = kNaN;
      out_prim[i] = -1;
    }
  }
  // Counted apart, by comparisons that vectorize: a ++count[label] per point was a chain of
  // stores and reloads of the same counter (nine points in ten are planes).
  std::array<std::uint32_t, kNumLabels> counts{};
  for (std::size_t i = 0; i < n; ++i)
    for (std::size_t l = 1; l < kNumLabels; ++l) counts[l] += out_label[i] == l;
  std::size_t labelled = 0;
  for (std::size_t l = 1; l < kNumLabels; ++l)
  {
    out.label_counts[l] += counts[l];
    labelled += counts[l];
  }
  out.label_counts[static_cast<std::size_t>(Label::None)] += n - labelled;
  out.times.output = msSince(t);
  return Status::success();
}

}  // namespace ring_curvature
