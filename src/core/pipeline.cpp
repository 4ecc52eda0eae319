#include "ring_curvature/pipeline.hpp"

#include <algorithm>
#include <array>
#include <chrono>
#include <cstring>
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

// Points of each label but None among labels[0, n) (counts[0] is left alone). Sixteen bytes at a
// time: a match compares to all ones (-1), subtracted into one byte counter per lane and label,
// and the counters are summed out before they can wrap (every 255 groups). Written as vectors:
// the plain loop the compiler vectorized widened every comparison to 32 bits (four instructions
// a label, where these are one compare and one subtract a label per sixteen).
using V16u8 = std::uint8_t __attribute__((vector_size(16)));
void countLabels(const std::uint8_t* labels, std::size_t n, std::array<std::uint32_t, kNumLabels>& counts)
{
  constexpr std::size_t kGroup = sizeof(V16u8), kMaxGroups = 255;
  const std::size_t whole = n / kGroup * kGroup;
  std::size_t i = 0;
  while (i < whole)
  {
    V16u8 acc[kNumLabels] = {};
    const std::size_t stop = std::min(whole, i + kMaxGroups * kGroup);
    for (; i < stop; i += kGroup)
    {
      V16u8 v;
      std::memcpy(&v, labels + i, sizeof v);
      for (std::size_t l = 1; l < kNumLabels; ++l) acc[l] -= reinterpret_cast<V16u8>(v == static_cast<std::uint8_t>(l));
    }
    for (std::size_t l = 1; l < kNumLabels; ++l)
      for (std::size_t j = 0; j < kGroup; ++j) counts[l] += acc[l][j];
  }
  for (; i < n; ++i)
    for (std::size_t l = 1; l < kNumLabels; ++l) counts[l] += labels[i] == l ? 1u : 0u;
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
  // Counted apart, sixteen labels at a time (countLabels): a ++count[label] per point was a chain
  // of stores and reloads of the same counter (nine points in ten are planes).
  std::array<std::uint32_t, kNumLabels> counts{};
  countLabels(out_label, n, counts);
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
