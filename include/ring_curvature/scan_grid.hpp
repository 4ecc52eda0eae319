// The ring x azimuth scan grid: every valid return placed on its ring, in azimuth order, with
// the map back to the input point index. Built in O(n) from a PointCloudView.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

#include "ring_curvature/params.hpp"
#include "ring_curvature/types.hpp"

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

  // per grid position
  std::vector<std::uint32_t> index;   ///< input point index
  // double: float64 input keeps its precision, and the convergence study (paper Table 1)
  // reaches steps where float32 rounding of coordinates would dominate the error.
  std::vector<double> x, y, z;
  std::vector<double> range;          ///< 3-D range rho [m]
  std::vector<float> azimuth;         ///< [rad] in [-pi, pi)
  std::vector<std::uint8_t> linked;   ///< 1 when connected to its predecessor on the ring (no gap)
  std::vector<std::int32_t> up;       ///< nearest position on ring n+1 (azimuth), -1 if none

  // per input point
  std::vector<PointState> state;
  std::vector<std::int32_t> grid_pos; ///< grid position (for Duplicate: its representative), or -1
  std::vector<std::uint32_t> duplicates;  ///< input indices of the Duplicate points, ascending

  std::size_t num_input = 0, num_valid = 0, num_duplicates = 0, num_second_returns = 0;

  std::size_t size() const { return index.size(); }
  std::uint32_t ringSize(int n) const { return ring_begin[n + 1] - ring_begin[n]; }
  /// Ring of a grid position (binary search over ring_begin; for tools, not hot loops).
  int ringOf(std::uint32_t pos) const;
};

/// Builds a ScanGrid from a view, reusing its own scratch buffers between frames.
class ScanGridBuilder
{
public:
  /// Validates the view against `params` (sizes, fields, ring range) and builds the grid.
  /// On error the grid is left empty and the status names the problem.
  Status build(const PointCloudView& view, const Params& params, ScanGrid& grid);

private:
  Status readPoints(const PointCloudView& view, const Params& params, ScanGrid& grid);
  void assignRingsFromElevation(const PointCloudView& view, const Params& params, ScanGrid& grid);
  void sortRings(const Params& params, ScanGrid& grid);
  void placeOrganized(const PointCloudView& view, ScanGrid& grid);
  void measureResolution(const Params& params, ScanGrid& grid);
  void removeDuplicates(const Params& params, ScanGrid& grid);
  void linkRings(const Params& params, ScanGrid& grid);
  void findVerticalNeighbours(ScanGrid& grid);

  // scratch, per input point
  std::vector<std::int32_t> ring_of_;
  std::vector<double> prange_;
  std::vector<float> paz_;
  // scratch, per ring / bin
  std::vector<std::uint32_t> counts_, bin_start_;
  std::vector<std::uint32_t> tmp_index_;
  std::vector<float> tmp_f_;
  std::vector<double> elev_sum_;
  std::vector<std::uint32_t> column_;  // organized: input column of each grid position
};

/// Fast atan2 (max error ~1e-5 rad) used for azimuths; exposed for tests. Inline: it runs once
/// per point in the grid and once per turning angle in the features (an out-of-line call was
/// ~10 % of a frame under perf).
inline float fastAtan2(float y, float x)
{
  const float ax = std::fabs(x), ay = std::fabs(y);
  const float mx = std::max(ax, ay), mn = std::min(ax, ay);
  if (!(mx > 0.0f)) return 0.0f;
  const float a = mn / mx;
  const float s = a * a;
  // Minimax polynomial for atan on [0, 1] (max error ~1e-5 rad, far below a 0.1 deg azimuth step).
  float r = ((((0.0208351f * s - 0.0851330f) * s + 0.1801410f) * s - 0.3302995f) * s + 0.9998660f) * a;
  if (ay > ax) r = 1.57079637f - r;
  if (x < 0.0f) r = 3.14159265358979f - r;
  return y < 0.0f ? -r : r;
}

}  // namespace ring_curvature
