// cutRing's AVX2 and AVX-512 forms and the index fill's AVX2 form (see primitive_runs.hpp).
#include "primitive_runs.hpp"

#include "compress_table.hpp"
#include "simd_clones.hpp"

#include <cstring>
#if defined(RC_SIMD_CLONES_ON)
#include <immintrin.h>
#endif

namespace ring_curvature
{

#if defined(RC_SIMD_CLONES_ON)

// The scalar cutRing loops once per run, and the end of a run (its length is data) is a
// mispredicted branch, about one a run. Here no branch depends on the data: a position's run id
// is the number of wanted runs opened up to it (a prefix count of the run starts in each group
// of eight, from a table), and the runs' begins and ends are listed by left-packing (the
// compress table). A run starts where join is 0 (and at b: join[b] is not written); a run of
// a wanted label ends where the next position starts a run, or at e. Every position of an
// unwanted label is a run of its own (join needs a wanted label), so its run id is `none`.
__attribute__((target("avx2,popcnt"))) std::size_t cutRingAvx2(
    std::uint32_t b, std::uint32_t e, const Label* lab, const std::uint8_t* join, std::uint8_t num_wanted,
    std::uint32_t none, std::uint32_t* parent, std::uint32_t* run, std::int32_t* comp,
    PrimitiveExtractor::Run* runs, std::size_t num_runs, std::uint32_t* begins, std::uint32_t* ends)
{
  const __m128i zero = _mm_setzero_si128(), above = _mm_set1_epi8(static_cast<char>(num_wanted + 1));
  const __m256i none8 = _mm256_set1_epi32(static_cast<int>(none));
  std::size_t nb = 0, ne = 0;
  auto last = static_cast<std::int32_t>(num_runs) - 1;  // the id of the last wanted run opened
  for (std::uint32_t p = b; p < e; p += 8)
  {
    const std::uint32_t left = e - p;
    // the labels are the caller's array: not read past e (join is ours, padded)
    // (a copy of variable length went through the stack: a stalled reload every group)
    __m128i l8 = zero;
    if (left >= 8)
      l8 = _mm_loadl_epi64(reinterpret_cast<const __m128i*>(lab + p));
    else
      std::memcpy(&l8, lab + p, left);
    const __m128i j8 = _mm_loadl_epi64(reinterpret_cast<const __m128i*>(join + p));
    const __m128i jn = _mm_loadl_epi64(reinterpret_cast<const __m128i*>(join + p + 1));
    const unsigned valid = left >= 8 ? 0xFFu : (1u << left) - 1;
    // wanted: 0 < label < num_wanted + 1 (labels are 0 to 4: signed byte compares hold)
    const __m128i w = _mm_and_si128(_mm_cmpgt_epi8(l8, zero), _mm_cmpgt_epi8(above, l8));
    const unsigned W = static_cast<unsigned>(_mm_movemask_epi8(w)) & valid;
    unsigned S = static_cast<unsigned>(_mm_movemask_epi8(_mm_cmpeq_epi8(j8, zero))) & 0xFFu;
    unsigned N = static_cast<unsigned>(_mm_movemask_epi8(_mm_cmpeq_epi8(jn, zero))) & 0xFFu;
    S |= p == b ? 1u : 0u;
    N |= left <= 8 ? 1u << (left - 1) : 0u;  // e - 1 ends its run (join[e] is another ring's)
    const unsigned ws = S & W, we = N & W;
    const __m256i prefix = _mm256_loadu_si256(reinterpret_cast<const __m256i*>(kPrefix.lane[ws]));
    const __m256i ids = _mm256_add_epi32(prefix, _mm256_set1_epi32(last));
    const __m256i wanted = _mm256_cvtepi8_epi32(w);  // all ones where wanted
    _mm256_storeu_si256(reinterpret_cast<__m256i*>(run + p), _mm256_blendv_epi8(none8, ids, wanted));
    const __m256i pos = _mm256_set1_epi32(static_cast<int>(p));
    const __m256i bo = _mm256_loadu_si256(reinterpret_cast<const __m256i*>(kCompress.lane[ws]));
    _mm256_storeu_si256(reinterpret_cast<__m256i*>(begins + nb), _mm256_add_epi32(bo, pos));
    const __m256i eo = _mm256_loadu_si256(reinterpret_cast<const __m256i*>(kCompress.lane[we]));
    _mm256_storeu_si256(reinterpret_cast<__m256i*>(ends + ne),
                        _mm256_add_epi32(eo, _mm256_add_epi32(pos, _mm256_set1_epi32(1))));
    const auto opened = static_cast<std::size_t>(__builtin_popcount(ws));
    nb += opened;
    ne += static_cast<std::size_t>(__builtin_popcount(we));
    last += static_cast<std::int32_t>(opened);
  }
  // (nb == ne: every wanted run has one start and one end)
  for (std::size_t i = 0; i < nb; ++i)
  {
    const std::size_t k = num_runs + i;
    runs[k].begin = begins[i];
    runs[k].end = ends[i];
    parent[k] = static_cast<std::uint32_t>(k);
    comp[k] = 0;
  }
  return num_runs + nb;
}

// The index fill of extract (primitives.cpp: its plain loop says what is written) with AVX2:
// eight positions a step, the last step of a run or gap with masked loads and stores, so that
// a run of up to eight positions (most of them) takes one step and no branch on its length,
// where the plain loop took a branch on the length and one at the end of each loop.
__attribute__((target("avx2"))) void fillRunsAvx2(const PrimitiveExtractor::Run* runs, std::size_t num_runs,
                                                  const std::uint32_t* parent, const std::int32_t* comp,
                                                  const std::uint32_t* ring_begin, PrimitiveInfo* prims,
                                                  const std::uint32_t* index, std::uint32_t* indices,
                                                  std::uint32_t* slot_pos, std::int32_t* of_grid, std::uint32_t m)
{
  const __m256i lane = _mm256_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7), gap = _mm256_set1_epi32(-1);
  // (macros: a lambda does not take the function's target, and its vectors would change the ABI)
  // the lanes below `left` (left > 0)
#define RC_BELOW(left) _mm256_cmpgt_epi32(_mm256_set1_epi32(static_cast<int>((left) < 8 ? (left) : 8)), lane)
#define RC_FILL_GAP(from, end)                                                                        \
  for (std::uint32_t p = (from); p < (end); p += 8) _mm256_maskstore_epi32(of_grid + p, RC_BELOW((end) - p), gap)
  int n = 0;
  std::uint32_t written = 0;
  for (std::size_t k = 0; k < num_runs; ++k)
  {
    const std::uint32_t s = runs[k].begin, t = runs[k].end;
    const std::int32_t id = comp[parent[k]];
    if (id < 0) continue;
    RC_FILL_GAP(written, s);
    written = t;
    while (s >= ring_begin[n + 1]) ++n;
    PrimitiveInfo& pr = prims[id];
    if (runs[k].rank == 0) pr.ring_min = static_cast<std::uint16_t>(n);
    pr.ring_max = static_cast<std::uint16_t>(n);
    const std::uint32_t slot = pr.first + runs[k].rank, len = t - s;
    const __m256i ids = _mm256_set1_epi32(id);
    for (std::uint32_t o = 0; o < len; o += 8)
    {
      const __m256i mask = RC_BELOW(len - o);
      const __m256i v = _mm256_maskload_epi32(reinterpret_cast<const int*>(index + s + o), mask);
      _mm256_maskstore_epi32(reinterpret_cast<int*>(indices + slot + o), mask, v);
      _mm256_maskstore_epi32(reinterpret_cast<int*>(slot_pos + slot + o), mask,
                             _mm256_add_epi32(lane, _mm256_set1_epi32(static_cast<int>(s + o))));
      _mm256_maskstore_epi32(of_grid + s + o, mask, ids);
    }
  }
  RC_FILL_GAP(written, m);
#undef RC_FILL_GAP
#undef RC_BELOW
}
// For cutRingAvx512's run records: word w of three vectors (sixteen runs' {begin, end, rank})
// is run w / 3's begin (lane w / 3 of the begins) or end (lane 16 + w / 3: the ends); `keep`
// masks out the ranks.
struct TripleTable
{
  std::int32_t lane[3][16];
  std::uint32_t keep[3];
};
constexpr TripleTable makeTripleTable()
{
  TripleTable t{};
  for (int w = 0; w < 48; ++w)
  {
    const int field = w % 3;
    t.lane[w / 16][w % 16] = field == 0 ? w / 3 : field == 1 ? 16 + w / 3 : 0;
    if (field != 2) t.keep[w / 16] |= 1u << (w % 16);
  }
  return t;
}
inline constexpr TripleTable kTriples = makeTripleTable();

RC_AVX512_BEGIN  // (simd_clones.hpp: GCC 12's false -Wmaybe-uninitialized)
// cutRingAvx2 sixteen positions a step. The byte compares stay SSE2 (their movemasks are the
// masks: AVX-512F has no byte compares, and BW would add a feature to check for nothing); the
// begins and ends are left-packed by vpcompressd into a register (no table) and stored whole;
// the run ids are the prefix table's counts for each half, the upper half's raised by the
// lower half's starts.
__attribute__((target("avx512f,popcnt"))) std::size_t cutRingAvx512(
    std::uint32_t b, std::uint32_t e, const Label* lab, const std::uint8_t* join, std::uint8_t num_wanted,
    std::uint32_t none, std::uint32_t* parent, std::uint32_t* run, std::int32_t* comp,
    PrimitiveExtractor::Run* runs, std::size_t num_runs, std::uint32_t* begins, std::uint32_t* ends)
{
  const __m128i zero = _mm_setzero_si128(), above = _mm_set1_epi8(static_cast<char>(num_wanted + 1));
  const __m512i none16 = _mm512_set1_epi32(static_cast<int>(none));
  const __m512i lane = _mm512_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15);
  std::size_t nb = 0, ne = 0;
  auto last = static_cast<std::int32_t>(num_runs) - 1;  // the id of the last wanted run opened
  for (std::uint32_t p = b; p < e; p += 16)
  {
    const std::uint32_t left = e - p;
    __m128i l16 = zero;  // (not read past e, as in cutRingAvx2)
    if (left >= 16)
      l16 = _mm_loadu_si128(reinterpret_cast<const __m128i*>(lab + p));
    else
      std::memcpy(&l16, lab + p, left);
    const __m128i j16 = _mm_loadu_si128(reinterpret_cast<const __m128i*>(join + p));
    const __m128i jn = _mm_loadu_si128(reinterpret_cast<const __m128i*>(join + p + 1));
    const unsigned valid = left >= 16 ? 0xFFFFu : (1u << left) - 1;
    const __m128i w = _mm_and_si128(_mm_cmpgt_epi8(l16, zero), _mm_cmpgt_epi8(above, l16));
    const unsigned W = static_cast<unsigned>(_mm_movemask_epi8(w)) & valid;
    unsigned S = static_cast<unsigned>(_mm_movemask_epi8(_mm_cmpeq_epi8(j16, zero)));
    unsigned N = static_cast<unsigned>(_mm_movemask_epi8(_mm_cmpeq_epi8(jn, zero)));
    S |= p == b ? 1u : 0u;
    N |= left <= 16 ? 1u << (left - 1) : 0u;
    const unsigned ws = S & W, we = N & W;
    const auto low = static_cast<std::int32_t>(__builtin_popcount(ws & 0xFFu));
    const __m256i lo = _mm256_loadu_si256(reinterpret_cast<const __m256i*>(kPrefix.lane[ws & 0xFFu]));
    const __m256i hi = _mm256_add_epi32(
        _mm256_loadu_si256(reinterpret_cast<const __m256i*>(kPrefix.lane[ws >> 8])), _mm256_set1_epi32(low));
    const __m512i ids =
        _mm512_add_epi32(_mm512_inserti64x4(_mm512_castsi256_si512(lo), hi, 1), _mm512_set1_epi32(last));
    _mm512_storeu_si512(run + p, _mm512_mask_blend_epi32(static_cast<__mmask16>(W), none16, ids));
    const __m512i pos = _mm512_add_epi32(lane, _mm512_set1_epi32(static_cast<int>(p)));
    _mm512_storeu_si512(begins + nb, _mm512_maskz_compress_epi32(static_cast<__mmask16>(ws), pos));
    _mm512_storeu_si512(ends + ne, _mm512_maskz_compress_epi32(static_cast<__mmask16>(we),
                                                                _mm512_add_epi32(pos, _mm512_set1_epi32(1))));
    const auto opened = static_cast<std::size_t>(__builtin_popcount(ws));
    nb += opened;
    ne += static_cast<std::size_t>(__builtin_popcount(we));
    last += static_cast<std::int32_t>(opened);
  }
  // The runs' records sixteen at a time: begins and ends interleaved into {begin, end, rank}
  // by vpermt2d, three vectors for sixteen runs (rank masked out: the caller writes it), parent
  // k and comp 0 beside. Masked stores: nothing past the ring's runs (parent and comp of `none`
  // may follow them). cutRingAvx2's loop of one run a step took a fifth of this function's time.
  static_assert(sizeof(PrimitiveExtractor::Run) == 3 * sizeof(std::uint32_t), "Run is {begin, end, rank}");
  auto* const out = reinterpret_cast<std::uint32_t*>(runs + num_runs);
  for (std::size_t i = 0; i < nb; i += 16)
  {
    const std::size_t c = nb - i < 16 ? nb - i : 16;
    const std::uint64_t words = (std::uint64_t{1} << (3 * c)) - 1;  // (3 c <= 48 bits)
    const __m512i bg = _mm512_loadu_si512(begins + i), en = _mm512_loadu_si512(ends + i);
    for (int j = 0; j < 3; ++j)
    {
      const __m512i idx = _mm512_loadu_si512(kTriples.lane[j]);
      const auto keep = static_cast<__mmask16>((words >> (16 * j)) & kTriples.keep[j]);
      _mm512_mask_storeu_epi32(out + 3 * i + 16 * static_cast<std::size_t>(j), keep,
                               _mm512_permutex2var_epi32(bg, idx, en));
    }
    const auto below = static_cast<__mmask16>((1u << c) - 1);
    _mm512_mask_storeu_epi32(parent + num_runs + i, below,
                             _mm512_add_epi32(lane, _mm512_set1_epi32(static_cast<int>(num_runs + i))));
    _mm512_mask_storeu_epi32(comp + num_runs + i, below, _mm512_setzero_si512());
  }
  return num_runs + nb;
}

RC_AVX512_END
#endif

}  // namespace ring_curvature
