// LOAM's feature sets from the core's labels: per ring and sector the sharpest Edge/Corner and
// the flattest Plane points, with LOAM's rules (neighbour suppression, no occluded side of a
// depth jump, no surface running along the beam) and a per-ring voxel grid for the less flat set.
// The labels replace LOAM's curvature thresholds: foliage and clutter (Rough) give no points to
// match frame to frame, only their depth jumps (outlines, gaps) as map landmarks (less sharp).
// Reads the grid only (and the time field of the points it places in the sweep): no extra pass
// over the input, O(n) apart from the partial sorts of a few candidates per sector.
#pragma once

#include "ring_curvature/loam_features.hpp"
#include "ring_curvature/params.hpp"
#include "ring_curvature/scan_grid.hpp"
#include "ring_curvature/features.hpp"
#include "common/ring_index.hpp"

#include <cstdint>
#include <vector>

namespace ring_curvature
{

class LoamSelector
{
public:
  void select(const PointCloudView& view, const ScanGrid& grid, const Features& f, const std::vector<Label>& labels,
              const Params& params, LoamFeatures& out);

private:
  /// Excluded positions: the far side of depth jumps, surfaces along the beam (blocked_).
  void exclusions(const ScanGrid& grid, const Params& params);
  /// Picks up to `quota` of the candidates (keys in preference order) in that order, skipping
  /// blocked ones; each pick blocks its `suppression` linked neighbours on each side. Appends to
  /// `out` (and to `also` for the first `also_quota`).
  void pick(const ScanGrid& grid, const RingSpan& s, std::vector<std::uint64_t>& cand, int quota, int suppression,
            std::vector<std::uint32_t>& out, std::vector<std::uint32_t>* also, int also_quota);
  void block(const ScanGrid& grid, const RingSpan& s, std::uint32_t k, int suppression);
  /// Appends the Rough positions in [lo, hi) whose discontinuity exceeds min_jump (0: none).
  static void roughJumps(std::uint32_t lo, std::uint32_t hi, const Features& f, const std::vector<Label>& labels,
                         float min_jump, std::vector<std::uint32_t>& out);
  void lessFlat(const ScanGrid& grid, std::uint32_t b, std::uint32_t K, const std::vector<Label>& labels,
                const Params& params, LoamFeatures& out);
  void sweepTimes(const PointCloudView& view, const ScanGrid& grid, const Params& params, LoamFeatures& out);

  std::vector<std::uint8_t> blocked_;
  std::vector<std::uint64_t> sharp_, flat_;  // candidate keys of one sector
  std::vector<std::uint64_t> voxel_keys_;  // open-addressing set, one ring at a time
  std::vector<std::uint32_t> voxel_used_;
  std::vector<double> time_scratch_;
};

}  // namespace ring_curvature
