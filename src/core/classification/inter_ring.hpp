// Inter-ring evidence on the ring-wise labels (the paper's section 6.2, "early, selective
// inter-ring fusion"): a ring alone cannot tell a hedge from a wall or a pole from a wall's edge,
// the rings above and below can. Four steps, each with its switch in Params:
// - roughness over a 3-ring window: foliage is rough along and across rings, a plane or a
//   horizontal crease is not (its cross-ring residual is the same all along the ring);
// - no Edge or Corner in rough surroundings;
// - occlusion: only the near side of a depth jump is a Corner (the far side is its shadow);
// - thin objects: a narrow run in front of both its neighbours, stacked over rings, is Edge.
// Linear time: every position looks at O(1) neighbours, and the runs are one pass per ring.
#pragma once

#include "ring_curvature/features.hpp"
#include "ring_curvature/params.hpp"
#include "ring_curvature/scan_grid.hpp"

#include <cstdint>
#include <vector>

namespace ring_curvature
{

class InterRingRefiner
{
public:
  /// Whether any of the steps is on (robust classifier only: Algorithm 1 stays the paper's).
  static bool enabled(const Params& params);
  /// Revises `labels` (per grid position) with the evidence of the neighbouring rings.
  void refine(const ScanGrid& grid, const Features& f, const Params& params, std::vector<Label>& labels);

private:
  /// Nearest samples on the rings above and below within 1.5 azimuth steps (up_, down_).
  void verticalNeighbours(const ScanGrid& grid);
  /// Per position: rough both along the ring (S) and across rings (the cross-ring residual).
  void roughness(const ScanGrid& grid, const Features& f, const Params& params);
  /// The lower quartile of the finite values (0 when none).
  float lowerQuartile(const std::vector<float>& values);
  /// Share of rough samples in the window of p (its ring and the rings above and below, +-2).
  float roughShare(std::uint32_t p) const
  {
    int total = 0, rough = 0;
    for (const std::int32_t r : {static_cast<std::int32_t>(p), up_[p], down_[p]})
      if (r >= 0)
      {
        const std::uint8_t w = window_[static_cast<std::size_t>(r)];
        total += w >> 4;
        rough += w & 15;
      }
    return total > 0 ? static_cast<float>(rough) / static_cast<float>(total) : 0.0f;
  }
  /// Each sample's linked neighbours along its ring (prev_, next_).
  void ringLinks(const ScanGrid& grid);
  std::int32_t twoBack(std::uint32_t p) const
  {
    const std::int32_t q = prev_[p];
    return q >= 0 && prev_[static_cast<std::size_t>(q)] != static_cast<std::int32_t>(p) ? prev_[static_cast<std::size_t>(q)] : -1;
  }
  std::int32_t twoAhead(std::uint32_t p) const
  {
    const std::int32_t q = next_[p];
    return q >= 0 && next_[static_cast<std::size_t>(q)] != static_cast<std::int32_t>(p) ? next_[static_cast<std::size_t>(q)] : -1;
  }
  /// Per position: in a thin run (thin_).
  void thinRuns(const ScanGrid& grid, const Params& params);

  std::vector<std::int32_t> up_, down_;  // -1: none
  std::vector<std::int32_t> prev_, next_;  // linked neighbours along the ring, -1: none
  std::vector<std::uint8_t> window_;     // the 5-sample window along the ring: samples << 4 | rough ones
  std::vector<float> across_;            // rho - mean of the ranges above and below (NaN: none)
  std::vector<float> vert_, ring_s_;     // the cross-ring and ring-wise roughness, range-scaled
  std::vector<float> scratch_;
  std::vector<std::uint8_t> rough_, thin_;
};

}  // namespace ring_curvature
