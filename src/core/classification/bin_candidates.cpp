// The wanted values of a ring copied out for the exact selection, eight lanes at a time
// (see binned_selection.hpp).
#include "classification/binned_selection.hpp"
#include "common/float_bits.hpp"

#include "common/compress_table.hpp"
#include "common/simd_clones.hpp"

#include <cmath>
#include <cstring>

namespace ring_curvature
{
namespace detail
{
namespace
{
// Eight lanes (GCC vector extension, element-wise: the same bits as scalar code everywhere).
using V8f = float __attribute__((vector_size(32)));
using V8i = std::int32_t __attribute__((vector_size(32)));

// Stores the lanes of v whose `in` lanes are set at out + m, in order, and advances m (writes all
// eight). Branch-free: the wanted values are few and anywhere, so a branch would mispredict.
__attribute__((always_inline)) inline void appendLanes(const V8f& v, std::uint32_t mask, float* out, std::size_t& m)
{
  V8i lane;
  std::memcpy(&lane, kCompress.lane[mask], sizeof lane);
#if defined(__clang__)  // (the sanitizer and fuzz builds): no variable shuffle builtin, lane by lane
  V8f packed;
  for (int j = 0; j < 8; ++j) packed[j] = v[lane[j]];
#else
  const V8f packed = __builtin_shuffle(v, lane);
#endif
  std::memcpy(out + m, &packed, sizeof packed);
  m += static_cast<std::size_t>(__builtin_popcount(mask));
}
// The same for the wanted lanes of x[i, n) that group(j, v, in) gives for j = i, i + 8, ...;
// returns where it stopped.
template <class Group>
__attribute__((always_inline)) inline std::size_t appendGroups(std::size_t i, std::size_t n, Group group, float* out,
                                                               std::size_t& m)
{
  const V8i bit = {1, 2, 4, 8, 16, 32, 64, 128};
  for (; i + 8 <= n; i += 8)
  {
    V8f a;
    V8i in_a;
    group(i, a, in_a);
    V8i s = in_a & bit;  // the mask's bits, summed across the lanes
    s += __builtin_shufflevector(s, s, 4, 5, 6, 7, 0, 1, 2, 3);
    s += __builtin_shufflevector(s, s, 2, 3, 0, 1, 6, 7, 4, 5);
    s += __builtin_shufflevector(s, s, 1, 0, 3, 2, 5, 4, 7, 6);
    appendLanes(a, static_cast<std::uint32_t>(s[0]), out, m);
  }
  return i;
}
}  // namespace

RC_SIMD_CLONES std::size_t binCandidates(const float* x, std::size_t n, std::uint32_t b0, std::uint32_t b1, float* out)
{
  const auto c0 = static_cast<std::int32_t>(b0), c1 = static_cast<std::int32_t>(b1);
  const V8i v0 = {c0, c0, c0, c0, c0, c0, c0, c0}, v1 = {c1, c1, c1, c1, c1, c1, c1, c1};
  std::size_t m = 0;
  auto group = [&](std::size_t j, V8f& v, V8i& in) __attribute__((always_inline)) {
    V8i u;
    std::memcpy(&v, x + j, sizeof v);
    std::memcpy(&u, x + j, sizeof u);
    const V8i bin = u >> kBinShift;
    in = (bin == v0) | (bin == v1);
  };
  for (std::size_t i = appendGroups(0, n, group, out, m); i < n; ++i)
  {
    const std::uint32_t bin = floatBits(x[i]) >> kBinShift;
    out[m] = x[i];  // overwritten by the next one unless this one is wanted
    m += ((bin == b0) | (bin == b1)) ? 1 : 0;
  }
  return m;
}

RC_SIMD_CLONES std::size_t bandCandidates(const float* x, std::size_t n, float med, float lo, float hi, float* out,
                                          std::size_t& under)
{
  const V8f vmed = {med, med, med, med, med, med, med, med};
  const V8f vlo = {lo, lo, lo, lo, lo, lo, lo, lo}, vhi = {hi, hi, hi, hi, hi, hi, hi, hi};
  const V8i abs_mask = {0x7FFFFFFF, 0x7FFFFFFF, 0x7FFFFFFF, 0x7FFFFFFF,
                        0x7FFFFFFF, 0x7FFFFFFF, 0x7FFFFFFF, 0x7FFFFFFF};
  V8i below = {};  // minus the count per lane
  std::size_t m = 0;
  auto group = [&](std::size_t j, V8f& d, V8i& in) __attribute__((always_inline)) {
    V8f v;
    std::memcpy(&v, x + j, sizeof v);
    const V8f diff = v - vmed;
    V8i bits;
    std::memcpy(&bits, &diff, sizeof bits);
    bits &= abs_mask;  // fabs
    std::memcpy(&d, &bits, sizeof d);
    below += d < vlo;
    in = (d >= vlo) & (d <= vhi);
  };
  std::size_t i = appendGroups(0, n, group, out, m);
  std::uint32_t count = 0;
  for (int l = 0; l < 8; ++l) count -= static_cast<std::uint32_t>(below[l]);
  for (; i < n; ++i)
  {
    const float d = std::fabs(x[i] - med);
    count += d < lo ? 1u : 0u;
    out[m] = d;  // overwritten by the next one unless this one is wanted
    m += ((d >= lo) & (d <= hi)) ? 1 : 0;
  }
  under = count;
  return m;
}

}  // namespace detail
}  // namespace ring_curvature
