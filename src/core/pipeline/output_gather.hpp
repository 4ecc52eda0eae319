// The pipeline's last stage: the per-grid-position results gathered back to input order, and
// the label counts.
#pragma once

#include "ring_curvature/scan_grid.hpp"
#include "ring_curvature/types.hpp"

#include <array>
#include <cstddef>
#include <cstdint>

namespace ring_curvature
{
namespace detail
{

// The per-point outputs and their sources (raw pointers: a label byte store may alias anything, so
// through the vectors every data pointer would be reloaded after each one).
struct OutputArrays
{
  const PointState* state;
  const std::int32_t* grid_pos;
  const std::uint8_t* label;  // per grid position
  const float *curvature, *smoothness, *discontinuity;
  const std::int32_t* primitive;
  std::uint8_t* out_label;  // per input point
  float *out_curvature, *out_smoothness, *out_discontinuity;
  std::int32_t* out_primitive;
};

/// Input points [0, n) get their grid position's results (OnGrid, or Duplicate: their
/// representative's), the others none (Label::None, NaN, -1). The grid is not empty.
void gatherOutput(const OutputArrays& o, std::size_t n);
/// Points of each label but None among labels[0, n) (counts[0] is left alone).
void countLabels(const std::uint8_t* labels, std::size_t n, std::array<std::uint32_t, kNumLabels>& counts);

}  // namespace detail
}  // namespace ring_curvature
