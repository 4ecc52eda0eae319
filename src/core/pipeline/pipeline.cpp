// The whole core, one frame at a time: grid -> features -> thresholds -> labels -> primitives
// -> per-point output.
#include "ring_curvature/pipeline.hpp"

#include "pipeline/output_gather.hpp"
#include "pipeline/stages.hpp"

#include <algorithm>
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

void clearOutputs(FrameResult& out)
{
  out.label.clear();
  out.curvature.clear();
  out.smoothness.clear();
  out.discontinuity.clear();
  out.primitive.clear();
  out.primitives.clear();
}

// The counts of labels[0, n), and None for the rest of the `total` input points. Counted apart,
// sixteen labels at a time: a ++count[label] per point is a chain of stores and reloads of the
// same counter (nine points in ten are planes).
void countInto(const std::uint8_t* labels, std::size_t n, std::size_t total, FrameResult& out)
{
  std::array<std::uint32_t, kNumLabels> counts{};
  detail::countLabels(labels, n, counts);
  std::size_t labelled = 0;
  for (std::size_t l = 1; l < kNumLabels; ++l)
  {
    out.label_counts[l] += counts[l];
    labelled += counts[l];
  }
  out.label_counts[static_cast<std::size_t>(Label::None)] += total - labelled;
}
}  // namespace

Pipeline::Pipeline(const Params& params) : params_(params), stages_(std::make_unique<Stages>()) {}
Pipeline::~Pipeline() = default;
Pipeline::Pipeline(Pipeline&&) noexcept = default;
Pipeline& Pipeline::operator=(Pipeline&&) noexcept = default;

const ScanGrid& Pipeline::grid() const { return stages_->grid; }
const Features& Pipeline::features() const { return stages_->features; }
const std::vector<Label>& Pipeline::gridLabels() const { return stages_->labels; }
const std::vector<RingThresholds>& Pipeline::thresholds() const { return stages_->thresholds; }

void Pipeline::selectLoamFeatures(const PointCloudView& view, LoamFeatures& out)
{
  Stages& s = *stages_;
  s.loam_selector.select(view, s.grid, s.features, s.labels, params_, out);
}

Status Pipeline::setParams(const Params& params)
{
  Status st = params.validate();
  if (st) params_ = params;
  return st;
}

Status Pipeline::process(const PointCloudView& view, FrameResult& out, Scope scope)
{
  Stages& s = *stages_;
  out.times = StageTimes{};
  out.label_counts.fill(0);
  auto t = Clock::now();
  Status st = s.grid_builder.build(view, params_, s.grid);
  out.times.grid = msSince(t);
  if (!st)
  {
    clearOutputs(out);
    return st;
  }
  s.feature_computer.compute(s.grid, params_, s.features);
  out.times.features = msSince(t);
  s.classifier.computeThresholds(s.grid, s.features, params_, s.thresholds);
  out.times.thresholds = msSince(t);
  s.classifier.classify(s.grid, s.features, params_, s.thresholds, s.labels);
  s.inter_ring.refine(s.grid, s.features, params_, s.labels);
  out.times.classification = msSince(t);
  if (scope == Scope::GridLabels)
  {
    clearOutputs(out);
    countInto(reinterpret_cast<const std::uint8_t*>(s.labels.data()), s.labels.size(), s.grid.num_input, out);
    return Status::success();
  }
  s.primitive_extractor.extract(s.grid, s.labels, params_, out.primitives);
  out.times.primitives = msSince(t);

  // Gather back to input order. Duplicates take their representative's results; invalid
  // returns and second returns stay unlabelled.
  const std::size_t n = s.grid.num_input;
  out.label.resize(n);
  out.curvature.resize(n);
  out.smoothness.resize(n);
  out.discontinuity.resize(n);
  out.primitive.resize(n);
  const detail::OutputArrays o{s.grid.state.data(),
                               s.grid.grid_pos.data(),
                               reinterpret_cast<const std::uint8_t*>(s.labels.data()),
                               s.features.curvature.data(),
                               s.features.smoothness.data(),
                               s.features.discontinuity.data(),
                               out.primitives.of_grid.data(),
                               out.label.data(),
                               out.curvature.data(),
                               out.smoothness.data(),
                               out.discontinuity.data(),
                               out.primitive.data()};
  if (s.grid.size() > 0)
  {
    detail::gatherOutput(o, n);
  }
  else  // no point on the grid
  {
    std::fill(out.label.begin(), out.label.end(), static_cast<std::uint8_t>(Label::None));
    for (auto* v : {&out.curvature, &out.smoothness, &out.discontinuity})
      std::fill(v->begin(), v->end(), std::numeric_limits<float>::quiet_NaN());
    std::fill(out.primitive.begin(), out.primitive.end(), -1);
  }
  countInto(out.label.data(), n, n, out);
  out.times.output = msSince(t);
  return Status::success();
}

}  // namespace ring_curvature
