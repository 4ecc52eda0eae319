#include "ring_curvature/pipeline.hpp"
#include "cpu_tuning.hpp"
#include "ring_curvature/prefetch.hpp"
#include "simd_clones.hpp"

#if defined(RC_SIMD_CLONES_ON)
#include <immintrin.h>
#endif

#include <algorithm>
#include <array>
#include <chrono>
#include <cstring>
#include <limits>

namespace ring_curvature
{

namespace
{
using Clock = std::chrono::steady_clock;
double msSince(Clock::time_point& t)
{
  const auto now = Clock::now();
  const double ms = std::chrono::duration<double, std::milli>(now - t).count();
  t = now;
  return ms;
}

// The per-point outputs and where they come from (raw pointers: a label is a byte, and a byte
// store may alias anything, so through the vectors the compiler reloaded every data pointer after
// each label store).
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

// gatherOutput where gatherOutputAvx2 does not run (the AMD tuning profile, cpu_tuning.hpp, and
// CPUs without AVX2), eight points a group: a group whose points are all on the grid (most of a
// single-return frame) reads its entries without a test, one all off (an organized cloud's
// padding) stores the unlabelled values, and a mixed one (dual-return frames, where firsts and
// second returns alternate; the edges of the padding) reads each point's entries, or position
// 0's if it has none, and keeps them or the unlabelled values by selection: there gatherOutput's
// branch mispredicted. The floats are selected as their bits, so that the compiler selects
// rather than branches. grid_size > 0.
__attribute__((always_inline)) inline void gatherOutputGroups(const OutputArrays& o, std::size_t i0,
                                                              std::size_t i1)
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

#if defined(RC_SIMD_CLONES_ON)
RC_AVX512_BEGIN
// Points [i, i + 16): `on` the lanes on the grid (OnGrid 1 or Duplicate 2: state - 1 <= 1,
// unsigned), p0 the first one's position; true where they hold p0, p0 + 1, ... in turn (a run).
__attribute__((target("avx512f,avx512bw,avx512vl"), always_inline)) inline bool isRun(const std::uint8_t* state,
                                                                                      const std::int32_t* grid_pos,
                                                                                      std::size_t i, __mmask16& on,
                                                                                      std::int32_t& p0)
{
  const __m128i one = _mm_set1_epi8(1);
  on = _mm_cmple_epu8_mask(_mm_sub_epi8(_mm_loadu_si128(reinterpret_cast<const __m128i*>(state + i)), one), one);
  p0 = 0;
  if (on == 0) return true;
  p0 = grid_pos[i + static_cast<std::size_t>(__builtin_ctz(on))];
  const __m512i iota = _mm512_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15);
  const __m512i run = _mm512_maskz_expand_epi32(on, _mm512_add_epi32(iota, _mm512_set1_epi32(p0)));
  return _mm512_mask_cmpneq_epi32_mask(on, _mm512_loadu_si512(grid_pos + i), run) == 0;
}

// Whether a frame's output goes by runs (gatherOutputRunsAvx512): three in four of its first
// kRunsProbes groups are runs (organized rows, rings one after another). Interleaved rings (the
// VLP-16's, HDL-32E's) have none, and their frames go to gatherOutputGroups whole.
constexpr std::size_t kRunsProbes = 16, kRunsFallback = 64;
__attribute__((target("avx512f,avx512bw,avx512vl"))) bool outputByRuns(const OutputArrays& o, std::size_t n)
{
  const auto* const state = reinterpret_cast<const std::uint8_t*>(o.state);
  std::size_t runs = 0, k = 0;
  for (; k < kRunsProbes && 16 * k + 16 <= n; ++k)
  {
    __mmask16 on;
    std::int32_t p0;
    runs += isRun(state, o.grid_pos, 16 * k, on, p0) ? 1u : 0u;
  }
  return k == kRunsProbes && runs * 4 >= kRunsProbes * 3;
}

// gatherOutputGroups out of line and compiled for any CPU, for gatherOutputRunsAvx512's groups
// that are not runs. (Inlined there, it was compiled for AVX-512 and took 1.4 of its time on the
// VLP-16 dual-return frames; a second call site in Pipeline::process took it out of line there,
// 1.02-1.12, hence always_inline and this one out-of-line copy.)
__attribute__((noinline)) void gatherOutputGroupsApart(const OutputArrays& o, std::size_t i0, std::size_t i1)
{
  gatherOutputGroups(o, i0, i1);
}

// gatherOutputGroups on AVX-512 CPUs of the AMD profile (Zen 4, where the gathers still lose to
// the plain loops, cpu_tuning.hpp), sixteen points a group: where a group is a run (an organized
// cloud's rows, whose valid columns take the next positions in turn; clouds whose rings come one
// after another, as KITTI's), each array's entries are read from p0 in one masked load and
// expanded into the lanes on the grid, the others getting the unlabelled values (a group all off
// the grid stores those alone). A group that is not a run (a duplicate shares its
// representative's position; a ring's end, azimuths out of order) hands the next kRunsFallback
// points to gatherOutputGroups (KITTI: one group in thirty), then runs again. On the Zen 4 host
// of session 21 the stage took 0.43 of gatherOutputGroups' time on OS1-128 frames, 0.70 on KITTI
// ones (docs/benchmark.md). grid_size > 0.
__attribute__((target("avx512f,avx512bw,avx512vl"))) void gatherOutputRunsAvx512(const OutputArrays& o, std::size_t n)
{
  const __m512 nan = _mm512_set1_ps(std::numeric_limits<float>::quiet_NaN());
  const __m512i none = _mm512_set1_epi32(-1);
  // (locals: through `o`, every pointer was reloaded after each store)
  const auto* const state = reinterpret_cast<const std::uint8_t*>(o.state);
  const std::int32_t* const grid_pos = o.grid_pos;
  const std::uint8_t* const label = o.label;
  const float *const curvature = o.curvature, *const smoothness = o.smoothness, *const discontinuity = o.discontinuity;
  const std::int32_t* const primitive = o.primitive;
  std::uint8_t* const out_label = o.out_label;
  float *const out_c = o.out_curvature, *const out_s = o.out_smoothness, *const out_d = o.out_discontinuity;
  std::int32_t* const out_p = o.out_primitive;
  std::size_t i = 0;
  while (i + 16 <= n)
  {
    __mmask16 on;
    std::int32_t p0;
    if (!isRun(state, grid_pos, i, on, p0))
    {
      const std::size_t to = std::min(n, i + kRunsFallback);
      gatherOutputGroupsApart(o, i, to);
      i = to;
      continue;
    }
    // the run's entries in the low lanes, expanded into the lanes on the grid; the masked loads
    // read nothing past the run's last entry
    const auto take = static_cast<__mmask16>((1u << __builtin_popcount(on)) - 1u);
    const auto q = static_cast<std::size_t>(p0);
    _mm512_storeu_ps(out_c + i, _mm512_mask_expand_ps(nan, on, _mm512_maskz_loadu_ps(take, curvature + q)));
    _mm512_storeu_ps(out_s + i, _mm512_mask_expand_ps(nan, on, _mm512_maskz_loadu_ps(take, smoothness + q)));
    _mm512_storeu_ps(out_d + i, _mm512_mask_expand_ps(nan, on, _mm512_maskz_loadu_ps(take, discontinuity + q)));
    _mm512_storeu_si512(out_p + i, _mm512_mask_expand_epi32(none, on, _mm512_maskz_loadu_epi32(take, primitive + q)));
    // None is 0: the lanes off the grid get the zero the expand puts there
    const __m512i l = _mm512_cvtepu8_epi32(_mm_maskz_loadu_epi8(take, label + q));
    _mm_storeu_si128(reinterpret_cast<__m128i*>(out_label + i), _mm512_cvtepi32_epi8(_mm512_maskz_expand_epi32(on, l)));
    i += 16;
  }
  gatherOutputGroupsApart(o, i, n);
}
RC_AVX512_END

// gatherOutput eight points at a time with AVX2's masked gathers (the compiler emits none for
// the plain loop): the scalar loop spent ~20 instructions a point, most of them loads and stores
// one value at a time and reloads of pointers it had no registers for. A label is gathered as
// the 32 bits at its address, so a group whose positions reach into the last three bytes of
// the labels is left to gatherOutput (as are the last n % 8 points). Returns the points done.
__attribute__((target("avx2"))) std::size_t gatherOutputAvx2(const OutputArrays& o, std::size_t n,
                                                             std::size_t grid_size)
{
  if (grid_size < 4) return 0;
  const __m256i one = _mm256_set1_epi32(static_cast<int>(PointState::OnGrid));
  const __m256i two = _mm256_set1_epi32(static_cast<int>(PointState::Duplicate));
  const __m256i last = _mm256_set1_epi32(static_cast<int>(grid_size - 4));  // last whole 32 bits
  const __m256i none = _mm256_set1_epi32(-1), byte = _mm256_set1_epi32(0xFF);
  const __m256 nan = _mm256_set1_ps(std::numeric_limits<float>::quiet_NaN());
  const auto* const label = reinterpret_cast<const int*>(o.label);
  const auto* const primitive = reinterpret_cast<const int*>(o.primitive);
  std::size_t i = 0;
  // (locals: the struct's pointers were reloaded after every store)
  float* const out_c = o.out_curvature;
  float* const out_s = o.out_smoothness;
  float* const out_d = o.out_discontinuity;
  std::int32_t* const out_p = o.out_primitive;
  for (; i + 8 <= n; i += 8)
  {
    {
      // The four 4-byte streams' lines kWriteAhead points ahead (prefetch.hpp), each asked for
      // twice (a line is two steps). Session 19's attempt at this took the stage 1.01-1.03;
      // with the pointers in locals, 0.94-0.99 (session 20).
      const std::size_t ahead = (i + detail::kWriteAhead) * sizeof(float);
      detail::prefetchForWrite(out_c, ahead);
      detail::prefetchForWrite(out_s, ahead);
      detail::prefetchForWrite(out_d, ahead);
      detail::prefetchForWrite(out_p, ahead);
    }
    const __m256i s = _mm256_cvtepu8_epi32(_mm_loadl_epi64(reinterpret_cast<const __m128i*>(o.state + i)));
    const __m256i on = _mm256_or_si256(_mm256_cmpeq_epi32(s, one), _mm256_cmpeq_epi32(s, two));
    const __m256i pos = _mm256_loadu_si256(reinterpret_cast<const __m256i*>(o.grid_pos + i));
    if (_mm256_movemask_epi8(_mm256_and_si256(on, _mm256_cmpgt_epi32(pos, last))) != 0)
    {
      gatherOutput(o, i, i + 8);
      continue;
    }
    const __m256 on_ps = _mm256_castsi256_ps(on);
    _mm256_storeu_ps(out_c + i, _mm256_mask_i32gather_ps(nan, o.curvature, pos, on_ps, 4));
    _mm256_storeu_ps(out_s + i, _mm256_mask_i32gather_ps(nan, o.smoothness, pos, on_ps, 4));
    _mm256_storeu_ps(out_d + i, _mm256_mask_i32gather_ps(nan, o.discontinuity, pos, on_ps, 4));
    _mm256_storeu_si256(reinterpret_cast<__m256i*>(out_p + i),
                        _mm256_mask_i32gather_epi32(none, primitive, pos, on, 4));
    // None is 0: the masked-off lanes keep the zero they start with
    const __m256i l = _mm256_and_si256(_mm256_mask_i32gather_epi32(_mm256_setzero_si256(), label, pos, on, 1), byte);
    const __m128i w = _mm_packus_epi32(_mm256_castsi256_si128(l), _mm256_extracti128_si256(l, 1));
    _mm_storel_epi64(reinterpret_cast<__m128i*>(o.out_label + i), _mm_packus_epi16(w, w));
  }
  return i;
}
#endif

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
}  // namespace

Pipeline::Pipeline(const Params& params) : params_(params) {}

Status Pipeline::setParams(const Params& params)
{
  Status st = params.validate();
  if (st) params_ = params;
  return st;
}

Status Pipeline::process(const PointCloudView& view, FrameResult& out)
{
  out.times = StageTimes{};
  out.label_counts.fill(0);
  auto t = Clock::now();
  Status st = grid_builder_.build(view, params_, grid_);
  out.times.grid = msSince(t);
  if (!st)
  {
    out.label.clear();
    out.curvature.clear();
    out.smoothness.clear();
    out.discontinuity.clear();
    out.primitive.clear();
    out.primitives.clear();
    return st;
  }
  feature_computer_.compute(grid_, params_, features_);
  out.times.features = msSince(t);
  classifier_.computeThresholds(grid_, features_, params_, thresholds_);
  out.times.thresholds = msSince(t);
  classifier_.classify(grid_, features_, params_, thresholds_, labels_);
  out.times.classification = msSince(t);
  primitive_extractor_.extract(grid_, labels_, params_, out.primitives);
  out.times.primitives = msSince(t);

  // Gather back to input order. Duplicates take their representative's results; invalid
  // returns and second returns stay unlabelled.
  const std::size_t n = grid_.num_input;
  out.label.resize(n);
  out.curvature.resize(n);
  out.smoothness.resize(n);
  out.discontinuity.resize(n);
  out.primitive.resize(n);
  const OutputArrays o{grid_.state.data(), grid_.grid_pos.data(), reinterpret_cast<const std::uint8_t*>(labels_.data()),
                       features_.curvature.data(), features_.smoothness.data(), features_.discontinuity.data(),
                       out.primitives.of_grid.data(), out.label.data(), out.curvature.data(), out.smoothness.data(),
                       out.discontinuity.data(), out.primitive.data()};
  std::size_t done = 0;
  const bool gathers = detail::avx2Gathers();  // (not on AMD, cpu_tuning.hpp: there gatherOutputGroups)
  bool runs = false;  // by runs where they pay (gatherOutputRunsAvx512: AMD profile, AVX-512)
#if defined(RC_SIMD_CLONES_ON)
  if (gathers) done = gatherOutputAvx2(o, n, grid_.size());
  runs = !gathers && grid_.size() > 0 && detail::avx512Forms() && __builtin_cpu_supports("avx512bw") &&
         __builtin_cpu_supports("avx512vl") && outputByRuns(o, n);
#endif
  // (a branch of its own: with `done = n` after the runs and the groups' call below as before,
  // GCC compiled the groups' loop slower, output 1.15-1.17 on the VLP-16 frames, session 21)
  if (runs)
  {
#if defined(RC_SIMD_CLONES_ON)
    gatherOutputRunsAvx512(o, n);
#endif
  }
  else if (grid_.size() > 0 && !gathers)
    gatherOutputGroups(o, done, n);
  else
    gatherOutput(o, done, n);
  const std::uint8_t* const out_label = out.label.data();
  // Counted apart, sixteen labels at a time (countLabels): a ++count[label] per point was a chain
  // of stores and reloads of the same counter (nine points in ten are planes).
  std::array<std::uint32_t, kNumLabels> counts{};
  countLabels(out_label, n, counts);
  std::size_t labelled = 0;
  for (std::size_t l = 1; l < kNumLabels; ++l)
  {
    out.label_counts[l] += counts[l];
    labelled += counts[l];
  }
  out.label_counts[static_cast<std::size_t>(Label::None)] += n - labelled;
  out.times.output = msSince(t);
  return Status::success();
}

}  // namespace ring_curvature
