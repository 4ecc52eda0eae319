// The whole core, one frame at a time: grid -> features -> thresholds -> labels -> primitives.
// ROS-free; the nodelet, the offline tools and the tests all call this class.
#pragma once

#include <array>
#include <cstdint>
#include <memory>
#include <vector>

#include "ring_curvature/classifier.hpp"
#include "ring_curvature/features.hpp"
#include "ring_curvature/loam_features.hpp"
#include "ring_curvature/params.hpp"
#include "ring_curvature/primitives.hpp"
#include "ring_curvature/scan_grid.hpp"
#include "ring_curvature/types.hpp"

namespace ring_curvature
{

/// Timing of the stages of one frame [ms] (steady clock).
struct StageTimes
{
  double grid = 0, features = 0, thresholds = 0, classification = 0, primitives = 0, output = 0;
  double total() const { return grid + features + thresholds + classification + primitives + output; }
};

/// Everything the pipeline produces for one frame. Per-point arrays are indexed like the input
/// (row-major for organized clouds) and have view.size() entries.
struct FrameResult
{
  std::vector<std::uint8_t> label;        ///< Label values
  std::vector<float> curvature;           ///< NaN where undefined or invalid
  std::vector<float> smoothness;
  std::vector<float> discontinuity;
  std::vector<std::int32_t> primitive;    ///< index into primitives.primitives, -1 for none
  PrimitiveSet primitives;
  std::array<std::size_t, kNumLabels> label_counts{};
  StageTimes times;
};

class Pipeline
{
public:
  explicit Pipeline(const Params& params = Params());
  ~Pipeline();
  Pipeline(Pipeline&&) noexcept;
  Pipeline& operator=(Pipeline&&) noexcept;

  /// Replaces the parameters (validated; on error the old ones stay in force).
  Status setParams(const Params& params);
  const Params& params() const { return params_; }

  /// How far process() goes.
  enum class Scope
  {
    Full,       ///< everything in FrameResult
    GridLabels  ///< up to the labels on the grid (what the LOAM sets need): no primitives and no
                ///< per-point arrays in input order; label_counts count the grid's points
  };

  /// Processes one frame. On error `out` holds an empty result and the status names the problem;
  /// the pipeline stays usable for the next frame.
  Status process(const PointCloudView& view, FrameResult& out, Scope scope = Scope::Full);

  /// LOAM's feature sets of the last frame processed (loam_features.hpp), from its labels and
  /// scores. `view` must be that frame's: its time field places the points in the sweep.
  void selectLoamFeatures(const PointCloudView& view, LoamFeatures& out);

  /// Intermediate products of the last frame (for tools, tests and visualisation).
  const ScanGrid& grid() const;
  const Features& features() const;
  const std::vector<Label>& gridLabels() const;
  const std::vector<RingThresholds>& thresholds() const;

private:
  /// The stages and their products (src/core/pipeline/stages.hpp): each stage keeps its scratch
  /// from frame to frame, so that a warm pipeline allocates nothing.
  struct Stages;
  Params params_;
  std::unique_ptr<Stages> stages_;
};

}  // namespace ring_curvature
