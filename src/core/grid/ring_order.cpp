// One ring's keys put in azimuth order: an insertion sort of the nearly sorted firing order in
// which real drivers deliver a ring, or a bucket sort when it is not (no quadratic case).
#include "grid/scan_grid_builder.hpp"

#include "common/angles.hpp"
#include "common/grow.hpp"
#include "common/simd_clones.hpp"
#include "grid/sort_keys.hpp"

#include <algorithm>
#include <cstring>

namespace ring_curvature
{

namespace
{
using namespace detail;

// The azimuth steps of a ring's k keys in their order, step[j] = az[j] - az[j - 1] (j >= 1), a
// flag where a step goes beyond -pi or pi, and how many steps go down.
RC_SIMD_CLONES std::uint32_t arrivalSteps(const std::uint64_t* __restrict src, std::size_t k,
                                          float* __restrict step, std::uint8_t* __restrict wide)
{
  std::uint32_t down = 0;
  for (std::size_t j = 1; j < k; ++j)
  {
    const float d = keyAzimuth(src[j]) - keyAzimuth(src[j - 1]);
    step[j] = d;
    wide[j] = ((d < -kPi) | (d > kPi)) ? 1 : 0;
    down += d < 0.0f ? 1u : 0u;
  }
  return down;
}
}  // namespace

void ScanGridBuilder::sortRing(const std::uint64_t* src, std::uint64_t* dst, std::uint32_t k)
{
  if (k < 2)
  {
    std::copy(src, src + k, dst);
    return;
  }
  std::uint32_t wrap_fwd, wrap_bwd;
  const std::uint32_t down = arrivalWraps(src, k, wrap_fwd, wrap_bwd);
  if (!sortAsArrived(src, dst, k, down, wrap_fwd, wrap_bwd)) bucketSort(src, dst, k);
}

std::uint32_t ScanGridBuilder::arrivalWraps(const std::uint64_t* src, std::uint32_t k, std::uint32_t& wrap_fwd,
                                            std::uint32_t& wrap_bwd)
{
  // The steps vectorize; the few beyond +-pi (the seam, once or twice a ring) are then found
  // eight flags at a time and compared in order (the first of equals wins).
  growTo(steps_, k);
  growTo(wide_, k);
  const std::uint32_t down = arrivalSteps(src, k, steps_.data(), wide_.data());
  wrap_fwd = wrap_bwd = 0;
  float drop = -kPi, rise = kPi;
  const auto visit = [&](std::uint32_t j) {
    const float d = steps_[j];
    if (d < drop)
    {
      drop = d;
      wrap_fwd = j;
    }
    if (d > rise)
    {
      rise = d;
      wrap_bwd = j;
    }
  };
  std::uint32_t j = 1;
  for (; j + 8 <= k; j += 8)
  {
    std::uint64_t any;
    std::memcpy(&any, wide_.data() + j, sizeof any);
    if (any == 0) continue;
    for (std::uint32_t t = j; t < j + 8; ++t)
      if (wide_[t]) visit(t);
  }
  for (; j < k; ++j)
    if (wide_[j]) visit(j);
  return down;
}

bool ScanGridBuilder::sortAsArrived(const std::uint64_t* src, std::uint64_t* dst, std::uint32_t k,
                                    std::uint32_t down, std::uint32_t wrap_fwd, std::uint32_t wrap_bwd)
{
  // Drivers deliver a ring in firing order: monotonic in azimuth with one wrap across +-pi and
  // local disorder. Read from the wrap (backwards if mostly decreasing) it is nearly sorted, so
  // insertion sort is about linear; a move budget hands anything else to bucketSort.
  // (Any choice of seam gives the same final order; it only decides how much is moved.)
  const std::size_t budget = 8 * static_cast<std::size_t>(k);
  std::size_t moves = 0;
  std::uint32_t j = 0;  // keys placed so far
  auto insert = [&](std::uint64_t v) {
    std::uint32_t q = j++;
    while (q > 0 && v < dst[q - 1] && moves < budget)
    {
      dst[q] = dst[q - 1];
      --q;
      ++moves;
    }
    dst[q] = v;
  };
  // Rotated to start after the wrap (reversed first if mostly decreasing), read straight from src.
  const auto forwards = [&](std::uint32_t lo, std::uint32_t hi) {  // src[lo], ..., src[hi - 1]
    for (std::uint32_t i = lo; i < hi && moves < budget; ++i) insert(src[i]);
  };
  const auto backwards = [&](std::uint32_t lo, std::uint32_t hi) {  // src[hi - 1], ..., src[lo]
    for (std::uint32_t t = hi; t > lo && moves < budget; --t) insert(src[t - 1]);
  };
  if (down > k / 2)
  {
    const std::uint32_t start = wrap_bwd > 0 ? wrap_bwd - 1 : k - 1;  // reversed, then rotated
    backwards(0, start + 1);
    backwards(start + 1, k);
  }
  else
  {
    forwards(wrap_fwd, k);
    forwards(0, wrap_fwd);
  }
  return moves < budget;
}

void ScanGridBuilder::bucketSort(const std::uint64_t* src, std::uint64_t* dst, std::uint32_t k)
{
  // Bucket sort by azimuth with about one bucket per point, then std::sort inside each bucket
  // (an insertion sort for the few keys of most, no quadratic case for a crowded one).
  std::uint32_t nb = 16;
  while (nb < k) nb <<= 1;
  const float scale = static_cast<float>(nb) / kTwoPi;
  auto binOf = [&](std::uint64_t key) {
    return std::min<std::uint32_t>(nb - 1, static_cast<std::uint32_t>((keyAzimuth(key) + kPi) * scale));
  };
  counts_.assign(nb + 1, 0);
  for (std::uint32_t j = 0; j < k; ++j) ++counts_[binOf(src[j]) + 1];
  for (std::uint32_t j = 0; j < nb; ++j) counts_[j + 1] += counts_[j];
  bin_start_.assign(counts_.begin(), counts_.end() - 1);
  for (std::uint32_t j = 0; j < k; ++j) dst[bin_start_[binOf(src[j])]++] = src[j];
  for (std::uint32_t j = 0; j < nb; ++j) std::sort(dst + counts_[j], dst + counts_[j + 1]);
}

}  // namespace ring_curvature
