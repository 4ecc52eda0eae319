// The per-point outputs gathered back to input order (see output_gather.hpp).
#include "pipeline/output_gather.hpp"

#include <algorithm>
#include <cstring>
#include <limits>

namespace ring_curvature
{
namespace detail
{

// Walks the input in order, so the writes are sequential and each entry is written once; the
// reads follow the rings (a few cached streams per array).
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

// Eight points a group: all on the grid reads without a test, any other group (dual returns,
// organized padding) reads each point's entries (position 0's if none) and selects, as a branch
// would mispredict; floats as bits, so the compiler selects too.
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
  // (locals: through `o` every pointer would be reloaded after each label's byte store)
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
    // (not unrolled: unrolled, its pointers outnumber the registers and spill to the stack)
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

// Sixteen bytes at a time: a match (-1) is subtracted into byte counters per lane and label, summed
// out before they wrap (every 255 groups); vectors, as the compiler widens comparisons to 32 bits.
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
