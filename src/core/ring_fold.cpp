// Folding of identical dual returns, ring by ring: after the scatter by ring, a pass over each
// ring's keys in firing order keeps the points that differ from both keys before them and lists
// the others as followers of their twin (resolveFollowers gives them its verdict). Eight keys at
// a time on AVX-512, four on AVX2, with the same result as the plain loop.
#include "ring_curvature/scan_grid.hpp"

#include "compress_table.hpp"
#include "cpu_tuning.hpp"
#include "simd_clones.hpp"

#if defined(RC_SIMD_CLONES_ON)
#include <immintrin.h>
#endif

#include <cstddef>
#include <cstring>

namespace ring_curvature
{

namespace
{
inline std::uint64_t rangeBits(const double* range, std::uint64_t key)
{
  std::uint64_t b;
  std::memcpy(&b, &range[static_cast<std::uint32_t>(key)], sizeof b);
  return b;
}

// Keys j in [from, k) of one ring, plain: key j is a follower when its azimuth key and range bits
// equal those of key j - 1 or j - 2 as they came (`p1`, `p2`: the ring's raw keys before j, its
// sentinels at first). Kept keys are packed from `w` on (w <= j, so the keys still to read are
// intact); followers go to `out`. Returns the new number of kept keys.
template <class Follower>
std::uint32_t foldPlain(std::uint64_t* keys, std::uint32_t from, std::uint32_t k, std::uint32_t w, std::uint64_t p1,
                        std::uint64_t p2, const double* range, Follower* out, std::size_t& num_followers)
{
  std::uint64_t r1 = rangeBits(range, p1), r2 = rangeBits(range, p2);
  for (std::uint32_t j = from; j < k; ++j)
  {
    const std::uint64_t key = keys[j], r = rangeBits(range, key);
    const bool same1 = (((key ^ p1) >> 32) | (r ^ r1)) == 0;
    const bool same2 = (((key ^ p2) >> 32) | (r ^ r2)) == 0;
    const bool same = same1 | same2;
    // point in the low half, its twin in the high half: the layout of a Follower
    const std::uint64_t entry = (key & 0xFFFFFFFFu) | ((same1 ? p1 : p2) << 32);
    std::memcpy(&out[num_followers], &entry, sizeof entry);
    num_followers += same ? 1 : 0;
    keys[w] = key;
    w += same ? 0 : 1;
    p2 = p1;
    r2 = r1;
    p1 = key;
    r1 = r;
  }
  return w;
}

#if defined(RC_SIMD_CLONES_ON)
// foldPlain four keys at a time: the keys one and two places back are the current vector shifted
// in from the last one (no reload: the packed stores overwrite the raw keys behind), the ranges
// four loads per vector, kept keys and followers left-packed through the pair table. Starts at
// key j (after foldAvx512's), returns the keys done; `w`, `p1`, `p2` and the count continue the
// plain loop.
__attribute__((target("avx2,popcnt"))) std::uint32_t foldAvx2(std::uint64_t* keys, std::uint32_t j, std::uint32_t k,
                                                                std::uint32_t& w, std::uint64_t& p1,
                                                                std::uint64_t& p2, const double* range,
                                                                void* out, std::size_t& num_followers)
{
  auto* const followers = static_cast<std::uint64_t*>(out);  // (stored through __m256i, which may alias)
  const __m256i low = _mm256_set1_epi64x(0xFFFFFFFFLL);
  // the raw keys and range bits before the first vector: lanes 2 and 3 are j - 2 and j - 1
  __m256i prev = _mm256_set_epi64x(static_cast<long long>(p1), static_cast<long long>(p2), 0, 0);
  __m256i prev_r = _mm256_set_epi64x(static_cast<long long>(rangeBits(range, p1)),
                                     static_cast<long long>(rangeBits(range, p2)), 0, 0);
  std::uint32_t kept = w;
  const std::uint32_t from = j;
  std::size_t count = num_followers;
  for (; j + 4 <= k; j += 4)
  {
    const __m256i key = _mm256_loadu_si256(reinterpret_cast<const __m256i*>(keys + j));
    // The ranges by four loads and inserts: vpgatherqq was slower here (grid 1.013, in-process
    // A/B on the 29k dual-return frames), as gathers have been elsewhere on this machine.
#define RC_RANGE(l) static_cast<long long>(rangeBits(range, keys[j + (l)]))
    const __m256i r = _mm256_set_epi64x(RC_RANGE(3), RC_RANGE(2), RC_RANGE(1), RC_RANGE(0));
#undef RC_RANGE
    // two places back: [j-2, j-1, j, j+1]; one place back: [j-1, j, j+1, j+2]
    const __m256i key2 = _mm256_permute2x128_si256(prev, key, 0x21);
    const __m256i r2 = _mm256_permute2x128_si256(prev_r, r, 0x21);
    const __m256i key1 = _mm256_alignr_epi8(key, key2, 8), r1 = _mm256_alignr_epi8(r, r2, 8);
    const __m256i az = _mm256_srli_epi64(key, 32);
    const __m256i same1 =
        _mm256_and_si256(_mm256_cmpeq_epi64(az, _mm256_srli_epi64(key1, 32)), _mm256_cmpeq_epi64(r, r1));
    const __m256i same2 =
        _mm256_and_si256(_mm256_cmpeq_epi64(az, _mm256_srli_epi64(key2, 32)), _mm256_cmpeq_epi64(r, r2));
    const auto mask = static_cast<unsigned>(_mm256_movemask_pd(_mm256_castsi256_pd(_mm256_or_si256(same1, same2))));
    const __m256i keep = _mm256_loadu_si256(reinterpret_cast<const __m256i*>(kPairs.lane[~mask & 0xFu]));
    _mm256_storeu_si256(reinterpret_cast<__m256i*>(keys + kept), _mm256_permutevar8x32_epi32(key, keep));
    kept += static_cast<std::uint32_t>(__builtin_popcount(~mask & 0xFu));
    const __m256i twin = _mm256_blendv_epi8(key2, key1, same1);
    const __m256i follower = _mm256_or_si256(_mm256_and_si256(key, low), _mm256_slli_epi64(twin, 32));
    const __m256i pick = _mm256_loadu_si256(reinterpret_cast<const __m256i*>(kPairs.lane[mask]));
    _mm256_storeu_si256(reinterpret_cast<__m256i*>(followers + count), _mm256_permutevar8x32_epi32(follower, pick));
    count += static_cast<std::size_t>(__builtin_popcount(mask));
    prev = key;
    prev_r = r;
  }
  if (j > from)
  {
    alignas(32) std::uint64_t last[4];
    _mm256_store_si256(reinterpret_cast<__m256i*>(last), prev);
    p1 = last[3];
    p2 = last[2];
  }
  w = kept;
  num_followers = count;
  return j;
}

RC_AVX512_BEGIN  // (simd_clones.hpp: GCC 12's false -Wmaybe-uninitialized)
// foldAvx2 eight keys at a time with AVX-512F: the keys one and two places back by one valignq
// each, the comparisons as mask registers, and the left-packing by vpcompressq (no table). The
// packed stores are whole vectors, as in foldAvx2 (up to 7 followers past the count). Same
// contract: returns the keys done, the rest to foldAvx2 and the plain loop.
__attribute__((target("avx512f,popcnt"))) std::uint32_t foldAvx512(std::uint64_t* keys, std::uint32_t k,
                                                                    std::uint32_t& w, std::uint64_t& p1,
                                                                    std::uint64_t& p2, const double* range,
                                                                    void* out, std::size_t& num_followers)
{
  auto* const followers = static_cast<std::uint64_t*>(out);
  const __m512i low = _mm512_set1_epi64(0xFFFFFFFFLL);
  // the raw keys and range bits before the first vector: lanes 6 and 7 are j - 2 and j - 1
  __m512i prev = _mm512_set_epi64(static_cast<long long>(p1), static_cast<long long>(p2), 0, 0, 0, 0, 0, 0);
  __m512i prev_r = _mm512_set_epi64(static_cast<long long>(rangeBits(range, p1)),
                                    static_cast<long long>(rangeBits(range, p2)), 0, 0, 0, 0, 0, 0);
  std::uint32_t j = 0, kept = w;
  std::size_t count = num_followers;
  for (; j + 8 <= k; j += 8)
  {
    const __m512i key = _mm512_loadu_si512(keys + j);
#define RC_RANGE(l) static_cast<long long>(rangeBits(range, keys[j + (l)]))
    const __m512i r = _mm512_set_epi64(RC_RANGE(7), RC_RANGE(6), RC_RANGE(5), RC_RANGE(4), RC_RANGE(3), RC_RANGE(2),
                                       RC_RANGE(1), RC_RANGE(0));
#undef RC_RANGE
    // two places back: [j-2 .. j+5]; one place back: [j-1 .. j+6]
    const __m512i key2 = _mm512_alignr_epi64(key, prev, 6), r2 = _mm512_alignr_epi64(r, prev_r, 6);
    const __m512i key1 = _mm512_alignr_epi64(key, prev, 7), r1 = _mm512_alignr_epi64(r, prev_r, 7);
    const __m512i az = _mm512_srli_epi64(key, 32);
    const __mmask8 same1 =
        _mm512_mask_cmpeq_epi64_mask(_mm512_cmpeq_epi64_mask(r, r1), az, _mm512_srli_epi64(key1, 32));
    const __mmask8 same2 =
        _mm512_mask_cmpeq_epi64_mask(_mm512_cmpeq_epi64_mask(r, r2), az, _mm512_srli_epi64(key2, 32));
    const auto same = static_cast<__mmask8>(same1 | same2), keep = static_cast<__mmask8>(~same);
    _mm512_storeu_si512(keys + kept, _mm512_maskz_compress_epi64(keep, key));
    kept += static_cast<std::uint32_t>(__builtin_popcount(keep));
    const __m512i twin = _mm512_mask_blend_epi64(same1, key2, key1);
    const __m512i follower = _mm512_or_si512(_mm512_and_si512(key, low), _mm512_slli_epi64(twin, 32));
    _mm512_storeu_si512(followers + count, _mm512_maskz_compress_epi64(same, follower));
    count += static_cast<std::size_t>(__builtin_popcount(same));
    prev = key;
    prev_r = r;
  }
  if (j > 0)
  {
    alignas(64) std::uint64_t last[8];
    _mm512_store_si512(last, prev);
    p1 = last[7];
    p2 = last[6];
  }
  w = kept;
  num_followers = count;
  return j;
}
RC_AVX512_END
#endif
}  // namespace

std::uint32_t ScanGridBuilder::foldRing(std::uint64_t* keys, std::uint32_t k, std::uint64_t sentinel,
                                        const double* range, Follower* followers, std::size_t& num_followers)
{
  static_assert(sizeof(Follower) == sizeof(std::uint64_t) && offsetof(Follower, point) == 0 &&
                    offsetof(Follower, of) == sizeof(std::uint32_t),
                "a Follower is written as one 64-bit word: point low, twin high");
  std::uint32_t w = 0, j = 0;
  std::uint64_t p1 = sentinel, p2 = sentinel;
#if defined(RC_SIMD_CLONES_ON)
  if (detail::avx512Forms() && __builtin_cpu_supports("popcnt"))
    j = foldAvx512(keys, k, w, p1, p2, range, followers, num_followers);
  if (__builtin_cpu_supports("avx2") && __builtin_cpu_supports("popcnt"))
    j = foldAvx2(keys, j, k, w, p1, p2, range, followers, num_followers);
#endif
  return foldPlain(keys, j, k, w, p1, p2, range, followers, num_followers);
}

}  // namespace ring_curvature
