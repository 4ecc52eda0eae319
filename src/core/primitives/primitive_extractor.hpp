// The primitive stage (Section 4.3): connected components of same-label neighbours on the scan
// grid (union-find over runs, linear time) and a geometric summary of each component.
#pragma once

#include "ring_curvature/params.hpp"
#include "ring_curvature/primitives.hpp"
#include "ring_curvature/scan_grid.hpp"
#include "ring_curvature/uninitialized_vector.hpp"

#include <cstdint>
#include <vector>

namespace ring_curvature
{

class PrimitiveExtractor
{
public:
  void extract(const ScanGrid& grid, const std::vector<Label>& labels, const Params& params, PrimitiveSet& out);

  /// A maximal stretch [begin, end) of one ring whose neighbours all unite (Eq 19-20, same
  /// wanted label): one component without any union-find work per point.
  struct Run
  {
    std::uint32_t begin, end;
    std::uint32_t rank;  ///< points of its component before it (grid order)
  };

private:
  /// Cuts every ring into runs and unites the runs that touch, along and across rings; returns
  /// the number of runs.
  std::size_t uniteRuns(const ScanGrid& grid, const Label* lab, const Params& params);
  /// Each run's root, rank in its component and the components' sizes; returns the roots.
  std::size_t countComponents(std::size_t num_runs);
  /// The duplicates join their representative's component (and count at its grid position).
  void joinDuplicates(const ScanGrid& grid);
  /// Ids for the components large enough, in scan order; returns their points.
  std::uint32_t numberPrimitives(const Label* lab, const Params& params, std::size_t num_roots, PrimitiveSet& out);
  /// Every point's index in its primitive's slots, and of_grid.
  void fillIndices(const ScanGrid& grid, std::size_t num_runs, std::uint32_t total, PrimitiveSet& out);
  /// Box, centroid, covariance and axis of every primitive.
  void summarize(const ScanGrid& grid, PrimitiveSet& out);

  // Scratch, every entry written before it is read: a resize need not zero-fill what exceeds
  // the last frame's size.
  UninitializedVector<std::uint32_t> parent_;   // union-find forest over the run ids
  UninitializedVector<std::uint32_t> run_;      // run id of each grid position (unwanted label: none)
  UninitializedVector<std::uint8_t> join_;      // 1 where a position joins its predecessor's run
  UninitializedVector<Run> runs_;               // the runs of wanted labels, in grid order: by id
  UninitializedVector<std::int32_t> comp_;      // at each root: component size, then primitive id or -1
  UninitializedVector<std::uint32_t> roots_;    // the roots (run ids), in grid order
  UninitializedVector<std::uint32_t> grid_size_; // grid points per root, then per primitive id
  UninitializedVector<std::uint32_t> dup_root_; // root of each duplicate's component (none if unwanted)
  UninitializedVector<std::uint32_t> dup_rank_; // points of that component before the duplicate
  UninitializedVector<std::uint32_t> slot_pos_;  // grid position of each grid point's entry of PrimitiveSet::indices
  // Scratch kept zero between frames (a plain vector: a resize zero-fills new entries).
  std::vector<std::uint32_t> dup_count_;  // per grid position: the duplicates it represents
  std::uint32_t* dup_count_in_use_ = nullptr;  // dup_count_'s data while this frame has duplicates
  bool dup_count_zero_ = true;            // false while dup_count_ holds counts
};

}  // namespace ring_curvature
