// The grid stage: builds the ring x azimuth ScanGrid from a PointCloudView in O(n). One file a
// step: cloud_view_checks, input_pass, organized_placement, ring_sort / ring_order,
// resolution, scan_grid_builder.cpp (duplicates, gather, links), vertical_neighbours.
#pragma once

#include "grid/spacing_median.hpp"
#include "ring_curvature/params.hpp"
#include "ring_curvature/scan_grid.hpp"
#include "ring_curvature/types.hpp"
#include "ring_curvature/uninitialized_vector.hpp"

#include <cstddef>
#include <cstdint>
#include <vector>

namespace ring_curvature
{

/// Builds a ScanGrid from a view, reusing its own scratch buffers between frames.
class ScanGridBuilder
{
public:
  /// Validates the view against `params` (sizes, fields, ring range) and builds the grid.
  /// On error the grid is left empty and the status names the problem.
  Status build(const PointCloudView& view, const Params& params, ScanGrid& grid);

private:
  Status readPoints(const PointCloudView& view, const Params& params, ScanGrid& grid);  // input_pass.cpp
  void countRings(std::size_t n, const Params& params);
  void assignRingsFromElevation(const PointCloudView& view, const Params& params, ScanGrid& grid);
  /// A point identical (azimuth and range) to an earlier one of its ring, kept off the sort.
  struct Follower
  {
    std::uint32_t point, of;
  };
  void sortRings(ScanGrid& grid, bool fold_identical);  // ring_sort.cpp
  void sortEachRing(ScanGrid& grid);
  /// Scatters the points' sort keys into their rings, in input order (ring_sort.cpp).
  void scatterKeys(std::size_t n);
  /// Folds one ring's k keys in firing order in place: keeps a key unless its azimuth and range
  /// equal one of the two raw keys before it, listing the others in `followers` (writes one past).
  /// `sentinel` is a key whose range (range[index]) no point has. Returns the number kept.
  static std::uint32_t foldRing(std::uint64_t* keys, std::uint32_t k, std::uint64_t sentinel, const double* range,
                                Follower* followers, std::size_t& num_followers);
  void resolveFollowers(ScanGrid& grid);                 // ring_sort.cpp
  void sortRing(const std::uint64_t* src, std::uint64_t* dst, std::uint32_t k);
  /// How ring keys src[0, k) arrived: steps down in azimuth (returned), and where its largest
  /// drop and rise beyond -pi / pi are.
  std::uint32_t arrivalWraps(const std::uint64_t* src, std::uint32_t k, std::uint32_t& wrap_fwd,
                             std::uint32_t& wrap_bwd);
  /// Insertion sort in the order the ring arrived (nearly sorted); false when it ran out of its
  /// move budget (dst then holds nothing of use).
  static bool sortAsArrived(const std::uint64_t* src, std::uint64_t* dst, std::uint32_t k, std::uint32_t down,
                            std::uint32_t wrap_fwd, std::uint32_t wrap_bwd);
  /// Bucket sort by azimuth, for any order.
  void bucketSort(const std::uint64_t* src, std::uint64_t* dst, std::uint32_t k);
  void placeOrganized(const PointCloudView& view, ScanGrid& grid);  // organized_placement.cpp
  /// The input pass and the placement in one, for float32 x, y, z in a row and no ring or a uint16
  /// one, on AVX2 CPUs (else false); `largest` takes the largest ring field.
  bool readOrganized(const PointCloudView& view, const Params& params, ScanGrid& grid, std::uint32_t& largest);
  void measureResolution(const Params& params, ScanGrid& grid);  // resolution.cpp
  void gatherGrid(const PointCloudView& view, ScanGrid& grid);
  void removeDuplicates(const Params& params, ScanGrid& grid);
  void linkRings(const Params& params, ScanGrid& grid);
  void findVerticalNeighbours(ScanGrid& grid);

  // scratch, per input point
  std::vector<std::int32_t> ring_of_;
  std::vector<std::uint32_t> ring_count_;  // [0]: invalid points, [r + 1]: valid points of ring r
  std::vector<double> prange_;
  std::vector<float> paz_;
  UninitializedVector<float> px_, py_, pz_;  // each point's coordinates as float32
  // scratch, per ring / bin
  std::vector<std::uint32_t> counts_, bin_start_;
  UninitializedVector<std::uint32_t> tmp_index_;  // input index of each (sorted) grid position
  UninitializedVector<float> sorted_az_;          // and its azimuth
  UninitializedVector<std::uint64_t> keys_, keys_tmp_;  // (azimuth, input index) sort keys
  std::vector<float> steps_;        // one ring's azimuth steps in firing order (sortRing)
  std::vector<std::uint8_t> wide_;  // and where they go beyond +-pi
  std::vector<Follower> followers_;  // the first num_followers_ are this frame's
  std::size_t num_followers_ = 0;
  std::vector<std::uint32_t> ring_kept_;  // points of each ring left to sort
  std::uint32_t unfolded_largest_ = 0;  // the largest ring before folding (measureResolution)
  std::vector<float> tmp_f_;  // elevations; kept azimuth spacings
  std::vector<double> ring_sum_;  // each ring's sum of z / range (readOrganized)
  bool placed_ = false;           // readOrganized placed the frame on the grid
  SpacingMedian spacing_median_;
};

}  // namespace ring_curvature
