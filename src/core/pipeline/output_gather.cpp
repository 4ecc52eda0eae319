// The per-point outputs gathered back to input order (see output_gather.hpp).
#include "pipeline/output_gather.hpp"

#include <algorithm>
#include <cstring>

namespace ring_curvature
{
namespace detail
{

// Walks the input in order, so the writes are sequential and each entry is written once; the
// reads follow the rings (a few cached streams per array). Each point reads its grid position's
// entries (position 0's if none) and selects, as a branch on the state would mispredict (dual
// returns, organized padding); floats as bits, so the compiler selects too.
void gatherOutput(const OutputArrays& o, std::size_t n)
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
  // (not unrolled: unrolled, its pointers outnumber the registers and spill to the stack)
#pragma GCC unroll 1
  for (std::size_t j = 0; j < n; ++j)
  {
    const bool on = static_cast<std::uint8_t>(state[j] - 1u) < 2u;  // OnGrid (1) or Duplicate (2)
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
