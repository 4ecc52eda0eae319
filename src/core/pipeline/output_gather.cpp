// The per-point outputs gathered back to input order (see output_gather.hpp).
#include "pipeline/output_gather.hpp"

#include <algorithm>
#include <cstring>
#include <limits>

namespace ring_curvature
{
namespace detail
{

// Input points [i0, i1): those on the grid (OnGrid, or Duplicate: their representative's
// position) gather their grid position's results, the others get none. Walks the input in order:
// the writes are sequential and every entry is written once, while the reads follow the rings (a
// few streams per array, cached). Filling the arrays first and then scattering in grid order
// wrote each entry twice, with stores a cache line apart.
void gatherOutput(const OutputArrays& o, std::size_t i0, std::size_t i1)
{
  constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();
  for (std::size_t i = i0; i < i1; ++i)
  {
    if (o.state[i] == PointState::OnGrid || o.state[i] == PointState::Duplicate)
    {
      const auto p = static_cast<std::size_t>(o.grid_pos[i]);
      o.out_label[i] = o.label[p];
      o.out_curvature[i] = o.curvature[p];
      o.out_smoothness[i] = o.smoothness[p];
      o.out_discontinuity[i] = o.discontinuity[p];
      o.out_primitive[i] = o.primitive[p];
    }
    else
    {
      o.out_label[i] = static_cast<std::uint8_t>(Label::None);
      o.out_curvature[i] = kNaN;
      o.out_smoothness[i] = kNaN;
      o.out_discontinuity[i] = kNaN;
      o.out_primitive[i] = -1;
    }
  }
}

// gatherOutput eight points a group: a group whose points are all on the grid (most of a
// single-return frame) reads its entries without a test, one all off (an organized cloud's
// padding) stores the unlabelled values, and a mixed one (dual-return frames, where firsts and
// second returns alternate; the edges of the padding) reads each point's entries, or position
// 0's if it has none, and keeps them or the unlabelled values by selection: there gatherOutput's
// branch mispredicted. The floats are selected as their bits, so that the compiler selects
// rather than branches. grid_size > 0.
void gatherOutputGroups(const OutputArrays& o, std::size_t i0, std::size_t i1)
{
  const std::uint32_t nan_bits = 0x7fc00000u;  // std::numeric_limits<float>::quiet_NaN()
  const auto* const curvature = reinterpret_cast<const std::uint32_t*>(o.curvature);
  const auto* const smoothness = reinterpret_cast<const std::uint32_t*>(o.smoothness);
  const auto* const discontinuity = reinterpret_cast<const std::uint32_t*>(o.discontinuity);
  auto* const out_curvature = reinterpret_cast<std::uint32_t*>(o.out_curvature);
  auto* const out_smoothness = reinterpret_cast<std::uint32_t*>(o.out_smoothness);
  auto* const out_discontinuity = reinterpret_cast<std::uint32_t*>(o.out_discontinuity);
  const auto* const state = reinterpret_cast<const std::uint8_t*>(o.state);
  // (locals: through `o`, every pointer was reloaded after each label's byte store)
  const std::int32_t* const grid_pos = o.grid_pos;
  const std::uint8_t* const label = o.label;
  const std::int32_t* const primitive = o.primitive;
  std::uint8_t* const out_label = o.out_label;
  std::int32_t* const out_primitive = o.out_primitive;
  // OnGrid (1) or Duplicate (2)
  const auto onGrid = [state](std::size_t i) { return static_cast<std::uint8_t>(state[i] - 1u) < 2u; };
  std::size_t i = i0;
  for (; i + 8 <= i1; i += 8)
  {
    unsigned count = 0;
    for (std::size_t j = i; j < i + 8; ++j) count += onGrid(j) ? 1u : 0u;
    if (count == 8)
    {
      for (std::size_t j = i; j < i + 8; ++j)
      {
        const auto p = static_cast<std::size_t>(grid_pos[j]);
        out_label[j] = label[p];
        out_curvature[j] = curvature[p];
        out_smoothness[j] = smoothness[p];
        out_discontinuity[j] = discontinuity[p];
        out_primitive[j] = primitive[p];
      }
      continue;
    }
    if (count == 0)
    {
      for (std::size_t j = i; j < i + 8; ++j)
      {
        out_label[j] = static_cast<std::uint8_t>(Label::None);
        out_curvature[j] = out_smoothness[j] = out_discontinuity[j] = nan_bits;
        out_primitive[j] = -1;
      }
      continue;
    }
    // (a loop, not unrolled: unrolled eight times it held more pointers than there are
    // registers and reloaded them from the stack; the all-on loop above gains from unrolling)
#pragma GCC unroll 1
    for (std::size_t j = i; j < i + 8; ++j)
    {
      const bool on = onGrid(j);
      const auto p = static_cast<std::size_t>(on ? grid_pos[j] : 0);
      const std::uint8_t l = label[p];
      const std::uint32_t c = curvature[p], s = smoothness[p], d = discontinuity[p];
      const std::int32_t q = primitive[p];
      out_label[j] = on ? l : static_cast<std::uint8_t>(Label::None);
      out_curvature[j] = on ? c : nan_bits;
      out_smoothness[j] = on ? s : nan_bits;
      out_discontinuity[j] = on ? d : nan_bits;
      out_primitive[j] = on ? q : -1;
    }
  }
  gatherOutput(o, i, i1);
}

// Points of each label but None among labels[0, n) (counts[0] is left alone). Sixteen bytes at a
// time: a match compares to all ones (-1), subtracted into one byte counter per lane and label,
// and the counters are summed out before they can wrap (every 255 groups). Written as vectors:
// the plain loop the compiler vectorized widened every comparison to 32 bits (four instructions
// a label, where these are one compare and one subtract a label per sixteen).
using V16u8 = std::uint8_t __attribute__((vector_size(16)));
void countLabels(const std::uint8_t* labels, std::size_t n, std::array<std::uint32_t, kNumLabels>& counts)
{
  constexpr std::size_t kGroup = sizeof(V16u8), kMaxGroups = 255;
  const std::size_t whole = n / kGroup * kGroup;
  std::size_t i = 0;
  while (i < whole)
  {
    V16u8 acc[kNumLabels] = {};
    const std::size_t stop = std::min(whole, i + kMaxGroups * kGroup);
    for (; i < stop; i += kGroup)
    {
      V16u8 v;
      std::memcpy(&v, labels + i, sizeof v);
      for (std::size_t l = 1; l < kNumLabels; ++l) acc[l] -= reinterpret_cast<V16u8>(v == static_cast<std::uint8_t>(l));
    }
    for (std::size_t l = 1; l < kNumLabels; ++l)
      for (std::size_t j = 0; j < kGroup; ++j) counts[l] += acc[l][j];
  }
  for (; i < n; ++i)
    for (std::size_t l = 1; l < kNumLabels; ++l) counts[l] += labels[i] == l ? 1u : 0u;
}

}  // namespace detail
}  // namespace ring_curvature
