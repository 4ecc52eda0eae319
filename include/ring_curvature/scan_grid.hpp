// The ring x azimuth scan grid: every valid return placed on its ring, in azimuth order, with
// the map back to the input point index. Built in O(n) from a PointCloudView.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
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
  // vector's resize after clear() zero-filled each of them first, ~2 % of a frame's instructions)
  UninitializedVector<std::uint32_t> index;  ///< input point index
  // double: float64 input keeps its precision, and the convergence study (paper Table 1)
  // reaches steps where float32 rounding of coordinates would dominate the error.
  // (Uninitialized: the arrays below are resized each frame and then written in full.)
  UninitializedVector<double> x, y, z;
  UninitializedVector<double> range;  ///< 3-D range rho [m]
  UninitializedVector<float> azimuth;         ///< [rad] in [-pi, pi)
  UninitializedVector<std::uint8_t> linked;   ///< 1 when connected to its predecessor on the ring (no gap)
  UninitializedVector<std::int32_t> up;       ///< nearest position on ring n+1 (azimuth), -1 if none

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

/// The grid's measured azimuth resolution from the spacings d[0, total) of neighbouring samples
/// on a ring (each |difference| >= 0, or NaN): the median of the kept ones (above 1e-5 rad: not
/// a same-firing duplicate; below 5 deg: not a gap), i.e. the element of rank n / 2 of the n
/// kept, as nth_element would give; `none` when none is kept. Keeps its scratch between frames
/// (grid_resolution.cpp; a class of its own so that the tests reach both of its paths).
class SpacingMedian
{
public:
  /// d is overwritten when the frame is small or the sample's bracket misses.
  float operator()(float* d, std::size_t total, float none);
  /// Whether the last call found the median inside the bracket from its sample (else it
  /// selected among all the kept spacings).
  bool bracketed() const { return bracketed_; }

private:
  bool fromBracket(const float* d, std::size_t total, float& median);
  std::vector<std::uint32_t> inside_;  // the bits of the kept spacings near the median
  bool bracketed_ = false;
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
  /// The last two points kept of a ring as they came (azimuth key, range bits, input index),
  /// to fold identical returns (ring_sort.cpp).
  struct RingFold
  {
    std::uint32_t az1 = 0, az2 = 0;
    // the bits of -1.0 at first: no valid range is negative, so nothing matches before two points
    std::uint64_t r1 = 0xBFF0000000000000u, r2 = 0xBFF0000000000000u;
    std::uint32_t i1 = 0, i2 = 0;
  };
  /// A point identical (azimuth and range) to an earlier one of its ring, kept off the sort.
  struct Follower
  {
    std::uint32_t point, of;
  };
  void sortRings(ScanGrid& grid, bool fold_identical);  // ring_sort.cpp
  /// Scatters points [from, to) of rings interleaved point by point into their rings (ring_sort.cpp).
  void scatterInterleaved(std::size_t from, std::size_t to);
  /// Folds one ring's k keys in firing order in place (ring_fold.cpp): keeps a key unless its
  /// azimuth and range equal those of one of the two keys before it as they came, and lists the
  /// others in `followers` from `num_followers` on (up to 7 entries past the count are
  /// written). `sentinel` is a key whose range (range[index]) no point has. Returns the number kept.
  static std::uint32_t foldRing(std::uint64_t* keys, std::uint32_t k, std::uint64_t sentinel, const double* range,
                                Follower* followers, std::size_t& num_followers);
  void resolveFollowers(ScanGrid& grid);                 // ring_sort.cpp
  void sortRing(const std::uint64_t* src, std::uint64_t* dst, std::uint32_t k);
  /// Returns true when it also gathered the coordinates, set the grid positions and summed each
  /// ring's elevation sines (into ring_sum_): float32 clouds on AVX2 CPUs (grid_organized.cpp).
  bool placeOrganized(const PointCloudView& view, ScanGrid& grid);
  /// The input pass and placeOrganized's work in one pass, for organized float32 clouds with no
  /// ring field or a uint16 one, on AVX2 CPUs; false (nothing done) for any other. `largest`:
  /// the largest ring field read (grid_organized.cpp).
  bool readOrganized(const PointCloudView& view, const Params& params, ScanGrid& grid, std::uint32_t& largest);
  void measureResolution(const Params& params, ScanGrid& grid);  // grid_resolution.cpp
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
  std::vector<RingFold> ring_fold_;
  std::vector<float> steps_;        // one ring's azimuth steps in firing order (sortRing)
  std::vector<std::uint8_t> wide_;  // and where they go beyond +-pi
  std::vector<Follower> followers_;  // the first num_followers_ are this frame's
  std::size_t num_followers_ = 0;
  std::vector<std::uint32_t> follower_runs_;  // (begin, end) in followers_ of each ring's (resolveFollowers)
  std::size_t num_follower_runs_ = 0;
  std::vector<std::uint32_t> ring_kept_;  // points of each ring left to sort
  std::uint32_t unfolded_largest_ = 0;  // the largest ring before folding (measureResolution)
  std::vector<float> tmp_f_;  // elevations; kept azimuth spacings
  SpacingMedian spacing_median_;
  std::vector<double> ring_sum_;       // organized: each ring's sum of elevation sines
  bool placed_ = false;                // organized: readOrganized placed this frame's points
};

namespace detail
{
inline std::uint32_t floatBits(float f)
{
  std::uint32_t u;
  std::memcpy(&u, &f, sizeof u);
  return u;
}
inline float bitsFloat(std::uint32_t u)
{
  float f;
  std::memcpy(&f, &u, sizeof f);
  return f;
}
/// Float bits mapped to an unsigned key of the same order (negatives reversed, below positives;
/// -0 just below +0): integer comparisons and radix digits of keys order the floats.
inline std::uint32_t orderedKey(float f)
{
  const std::uint32_t u = floatBits(f);
  return u ^ ((0u - (u >> 31)) | 0x80000000u);
}
/// All ones when c, else zero.
inline std::uint32_t maskOf(bool c) { return 0u - static_cast<std::uint32_t>(c); }
/// mask ? a : b, bit for bit, without a branch.
inline float selectBits(std::uint32_t mask, float a, float b)
{
  return bitsFloat((floatBits(a) & mask) | (floatBits(b) & ~mask));
}
}  // namespace detail

/// Fast atan2 (max error ~1e-5 rad) used for azimuths; exposed for tests. Inline: it runs once
/// per point in the grid and once per turning angle in the features (an out-of-line call was
/// ~10 % of a frame under perf).
///
/// Written without branches so that loops over arrays of it are vectorized (four at a time):
/// with float comparisons and `?:` the compiler kept branches (a comparison may trap under the
/// default -ftrapping-math, and it skipped the division on the zero path), so the comparisons
/// are made on the bit patterns and the selections by masks. Each one reproduces the float
/// comparison exactly, NaN included (for |v|: v < w iff bits(v) < bits(w) and w is not NaN;
/// v < 0 iff 0x80000000 < bits(v) <= 0xff800000), so the result is bit for bit that of the
/// former branching version for every input (checked over all special values and 3e7 random
/// pairs): max(|x|, |y|) and min as std::max / std::min, a zero or NaN max gives +0.
inline float fastAtan2(float y, float x)
{
  using detail::floatBits;
  using detail::maskOf;
  using detail::selectBits;
  const float ax = std::fabs(x), ay = std::fabs(y);
  const std::uint32_t bx = floatBits(ax), by = floatBits(ay);
  const std::uint32_t x_lt_y = maskOf(bx < by) & maskOf(by <= 0x7f800000u);  // ax < ay
  const std::uint32_t y_lt_x = maskOf(by < bx) & maskOf(bx <= 0x7f800000u);  // ay < ax
  const float mx = selectBits(x_lt_y, ay, ax), mn = selectBits(y_lt_x, ay, ax);  // std::max, std::min
  const std::uint32_t bm = floatBits(mx);
  const std::uint32_t nonzero = maskOf(bm > 0u) & maskOf(bm <= 0x7f800000u);  // mx > 0
  const float a = mn / selectBits(nonzero, mx, 1.0f);  // the zero / NaN case divides by 1, discarded
  const float s = a * a;
  // Minimax polynomial for atan on [0, 1] (max error ~1e-5 rad, far below a 0.1 deg azimuth step).
  float r = ((((0.0208351f * s - 0.0851330f) * s + 0.1801410f) * s - 0.3302995f) * s + 0.9998660f) * a;
  r = selectBits(x_lt_y, 1.57079637f - r, r);
  const std::uint32_t sx = floatBits(x), sy = floatBits(y);
  r = selectBits(maskOf(sx > 0x80000000u) & maskOf(sx <= 0xff800000u), 3.14159265358979f - r, r);  // x < 0
  r = selectBits(maskOf(sy > 0x80000000u) & maskOf(sy <= 0xff800000u), -r, r);                      // y < 0
  return detail::bitsFloat(floatBits(r) & nonzero);  // +0 where mx is not > 0
}

}  // namespace ring_curvature
