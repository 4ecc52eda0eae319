// The organized float32 input pass: the record layout and grid arrays it works on, and its AVX2
// form (organized_avx2.cpp), the core's one hand-written SIMD form.
#pragma once

#include "common/simd_clones.hpp"
#include "ring_curvature/scan_grid.hpp"

#include <cstddef>
#include <cstdint>

namespace ring_curvature
{
namespace detail
{

/// Where a record's fields are, and the valid ranges.
struct RecordLayout
{
  std::size_t step;
  std::size_t ox, oy, oz;
  std::ptrdiff_t oring;  ///< -1: no ring field
  double rmin, rmax;
};

/// The grid's arrays the organized pass writes (index to range at grid positions, grid_pos and
/// state at input indices).
struct OrganizedGrid
{
  std::uint32_t* index;
  float* az;
  double *x, *y, *z, *range;
  std::int32_t* grid_pos;
  PointState* state;
};

#if defined(RC_SIMD_CLONES_ON)
/// Columns [0, cols) (cols a multiple of 8) of one row, records `L.step` bytes apart from `row`,
/// input indices from i0, read and their valid points placed from w on, eight at a time, as
/// placeColumn (organized_placement.cpp) does one at a time; `sum` takes z / range of the valid
/// ones, `largest` the largest uint16 ring field. Reads 16 bytes at each record's x and 4 at its
/// ring (the caller keeps them inside the data); writes up to 8 entries past the placed ones.
/// Needs AVX2 and POPCNT, y and z right after x. Returns the new w.
std::size_t readPlaceRowAvx2(const std::uint8_t* row, const RecordLayout& L, const OrganizedGrid& out, std::size_t i0,
                             std::size_t cols, std::size_t w, double& sum, std::uint32_t& largest);
#endif

}  // namespace detail
}  // namespace ring_curvature
