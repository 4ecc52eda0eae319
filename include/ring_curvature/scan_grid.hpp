// The ring x azimuth scan grid: every valid return placed on its ring, in azimuth order, with
// the map back to the input point index. Built in O(n) from a PointCloudView.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "ring_curvature/params.hpp"
#include "ring_curvature/types.hpp"
#include "ring_curvature/uninitialized_vector.hpp"

namespace ring_curvature
{

/// What became of one input point.
enum class PointState : std::uint8_t
{
  Invalid = 0,      ///< NaN / inf / out-of-range return: never fed into features
  OnGrid = 1,       ///< placed on the grid
  Duplicate = 2,    ///< same firing and same range as a grid point (dual return, identical)
  SecondReturn = 3, ///< same firing, different range: a second return off the grid
};

/// Structure-of-arrays scan grid. Positions p in [ring_begin[n], ring_begin[n+1]) hold ring n in
/// azimuth order. Arrays are reused across frames (no reallocation once warm).
struct ScanGrid
{
  int num_rings = 0;
  bool organized = false;
  float azimuth_resolution = 0.0f;      ///< [rad] measured (or given) sample spacing
  std::vector<std::uint32_t> ring_begin; ///< num_rings + 1 entries
  std::vector<float> ring_elevation;     ///< [rad] mean elevation phi_n of each ring
  std::vector<float> ring_cos;           ///< cos(phi_n)
  std::vector<std::uint8_t> ring_closed; ///< 1 when the ring's curve wraps across the 0/360 seam

  // per grid position (uninitialized vectors: every entry is written after each resize; a plain
  // vector's resize after clear() would zero-fill each of them first)
  UninitializedVector<std::uint32_t> index;  ///< input point index
  // double: float64 input keeps its precision, and the convergence study (paper Table 1)
  // reaches steps where float32 rounding of coordinates would dominate the error.
  // (Uninitialized: the arrays below are resized each frame and then written in full.)
  UninitializedVector<double> x, y, z;
  UninitializedVector<double> range;  ///< 3-D range rho [m]
  UninitializedVector<float> azimuth;         ///< [rad] in [-pi, pi)
  UninitializedVector<std::uint8_t> linked;   ///< 1 when connected to its predecessor on the ring (no gap)
  UninitializedVector<std::int32_t> up;       ///< nearest position on ring n+1 (azimuth), -1 if none
  /// Unorganized grids (empty when organized): the last position on ring n-1 at or before the
  /// azimuth, or that ring's first if none; -1 on ring 0 or above an empty ring.
  UninitializedVector<std::int32_t> below;

  // per input point
  UninitializedVector<PointState> state;
  UninitializedVector<std::int32_t> grid_pos; ///< grid position (for Duplicate: its representative), or -1
  UninitializedVector<std::uint32_t> duplicates;  ///< input indices of the Duplicate points, ascending

  std::size_t num_input = 0, num_valid = 0, num_duplicates = 0, num_second_returns = 0;
  /// Of the duplicates and second returns, those found identical to one of the last two points of
  /// their ring as they came (dual-return firing order), and so kept off the azimuth sort.
  std::size_t num_folded = 0;

  std::size_t size() const { return index.size(); }
  std::uint32_t ringSize(int n) const { return ring_begin[n + 1] - ring_begin[n]; }
  /// Ring of a grid position (binary search over ring_begin; for tools, not hot loops).
  int ringOf(std::uint32_t pos) const;
};

/// The ring of grid positions visited ring by ring (as the LOAM sets list them), in O(1)
/// amortized; a position before the current ring starts a new pass from ring 0.
struct RingCursor
{
  const ScanGrid& grid;
  int n = 0;
  int operator()(std::uint32_t p)
  {
    if (p < grid.ring_begin[static_cast<std::size_t>(n)]) n = 0;
    while (p >= grid.ring_begin[static_cast<std::size_t>(n) + 1]) ++n;
    return n;
  }
};

}  // namespace ring_curvature
