#include "ring_curvature/ros/outputs.hpp"

#include <sensor_msgs/PointField.h>

#include "ring_curvature/prefetch.hpp"
#include "ring_curvature/ros/recycle.hpp"

#include <boost/make_shared.hpp>
#include <algorithm>
#include <cstdint>
#include <cstring>
#include <limits>

namespace ring_curvature
{

namespace
{

sensor_msgs::PointField field(const std::string& name, std::uint32_t offset, std::uint8_t datatype)
{
  sensor_msgs::PointField f;
  f.name = name;
  f.offset = offset;
  f.datatype = datatype;
  f.count = 1;
  return f;
}

bool isAppendedName(const std::string& name)
{
  for (const char* n : kAppendedFieldNames)
    if (name == n)
      return true;
  return false;
}

// Zeroes the padding between an input record and its appended fields (0 to 3 bytes, before
// base): a zero word ending at base, written before the record, which overwrites its own part.
inline void padRecord(std::uint8_t* rec, std::size_t base)
{
  const std::uint32_t zero = 0;
  std::memcpy(rec + base - 4, &zero, 4);
}

// Copies one record of `n` bytes. Records are small (22 bytes for a velodyne XYZIRT, 48 for an
// ouster point) and a memcpy call per record with a run-time size was the largest cost of the
// output messages: whole 8-byte words instead, the last one overlapping its predecessor.
struct RunTimeCopy
{
  std::size_t n;
  void operator()(std::uint8_t* dst, const std::uint8_t* src) const
  {
    if (n < 8)
    {
      std::memcpy(dst, src, n);
      return;
    }
    std::uint64_t w;
    for (std::size_t k = 0; k + 8 < n; k += 8)
    {
      std::memcpy(&w, src + k, 8);
      std::memcpy(dst + k, &w, 8);
    }
    std::memcpy(&w, src + n - 8, 8);
    std::memcpy(dst + n - 8, &w, 8);
  }
  // The record, then zeros up to `base`, its length rounded up to 4 bytes (see padRecord).
  void padded(std::uint8_t* dst, const std::uint8_t* src, std::size_t base) const
  {
    padRecord(dst, base);
    (*this)(dst, src);
  }
};

// The common record sizes with the size known to the compiler: a few inline moves per record
// instead of the word loop (velodyne XYZIRT 22 bytes, ouster 48).
template <std::size_t N>
struct FixedCopy
{
  void operator()(std::uint8_t* dst, const std::uint8_t* src) const { std::memcpy(dst, src, N); }
  // As RunTimeCopy::padded (base is N rounded up to 4 bytes). A record of a multiple of 4 bytes
  // has no padding; the velodyne one's two padding bytes come with its last word: the 8 bytes
  // ending at byte 22, shifted down by two bytes, are bytes 16 .. 21 and two zeros
  // (little-endian), one store where the zero word and the overlapping last word were two (the
  // labelled cloud's pass is bound by its stores).
  void padded(std::uint8_t* dst, const std::uint8_t* src, std::size_t base) const
  {
    if constexpr (N % 4 == 0)
    {
      (void)base;
      std::memcpy(dst, src, N);
    }
#if defined(__BYTE_ORDER__) && __BYTE_ORDER__ == __ORDER_LITTLE_ENDIAN__
    else if constexpr (N == 22)
    {
      (void)base;
      std::memcpy(dst, src, 16);
      std::uint64_t w;
      std::memcpy(&w, src + 14, 8);
      w >>= 16;
      std::memcpy(dst + 16, &w, 8);
    }
#endif
    else
    {
      padRecord(dst, base);
      std::memcpy(dst, src, N);
    }
  }
};

// Calls f(copier) with the copier for records of `n` bytes.
template <class F>
void withCopier(std::size_t n, F f)
{
  switch (n)
  {
    case 22:
      f(FixedCopy<22>());
      break;
    case 48:
      f(FixedCopy<48>());
      break;
    default:
      f(RunTimeCopy{n});
  }
}

// Calls f(i, record) for every input point in order, walking rows and columns: a division and
// a modulo per point (to find its row) cost more than the rest of the copy. The message's sizes
// are read once: the callers write through byte pointers, which may alias them, so the compiler
// would reload them per point.
template <class F>
void forEachRecord(const sensor_msgs::PointCloud2& in, F f)
{
  std::size_t i = 0;
  // (a cloud without columns has no points, however many rows it declares)
  const std::uint32_t width = in.width, height = width > 0 ? in.height : 0;
  const std::size_t point_step = in.point_step, row_step = in.row_step;
  const std::uint8_t* const data = in.data.data();
  for (std::uint32_t row = 0; row < height; ++row)
  {
    const std::uint8_t* src = data + row * row_step;
    for (std::uint32_t col = 0; col < width; ++col, ++i, src += point_step)
      f(i, src);
  }
}

// Four 4-byte values (GCC/Clang vector extension; __builtin_shufflevector: clang, and GCC from
// 12, Debian 12's), read from any 4-byte type: only their bits are moved.
typedef std::uint32_t U32x4 __attribute__((vector_size(16)));
template <class T>
inline U32x4 loadU32x4(const T* p)
{
  static_assert(sizeof(T) == 4, "4-byte fields");
  U32x4 v;
  std::memcpy(&v, p, sizeof v);
  return v;
}

// The output clouds are written in a stream of stores to lines that are in no cache (a recycled
// buffer was last written a frame ago, a new one never): each store waits for its line, the store
// buffer fills and the pass stalls: it took 2.5 times as long as a memcpy of the same bytes. The
// lines kStoreAhead points ahead are asked for while the current ones are written: the labelled
// and plane clouds' pass took 0.67-0.70 of its time (in-process A/B over the 29k-point frames,
// 24, 48 and 96 points ahead alike; prefetchw, where the CPU has it, did no better).
constexpr std::size_t kStoreAhead = 48, kLine = 64;

// Prefetches `lines` cache lines from `offset` bytes past `p` on (the lines may lie past the
// buffer's end: ring_curvature/prefetch.hpp).
inline void prefetchLines(const std::uint8_t* p, std::size_t offset, std::size_t lines)
{
  for (std::size_t k = 0; k < lines; ++k)
    detail::prefetchForWrite(p, offset + k * kLine);
}

// Nothing more per point (makeLabelledCloud alone).
struct NoSubset
{
  void prefetch(std::size_t, std::size_t) const {}
  template <class Copy>
  void operator()(std::size_t, const std::uint8_t*, std::uint8_t*, Copy) const
  {
  }
};

// The records of the points labelled `label`, copied in order to dst .. end (sized for exactly
// those) while fillLabelled walks the input, so each record is read once for both clouds. Every
// record is copied and the pointer advances past kept ones only, as copySubset's dense loop
// does; once every kept record is in, the rest are copied into the labelled record about to be
// written (`scratch`, at least as long as an input record and overwritten next), not past end.
struct DenseSubset
{
  const std::uint8_t* label;
  std::uint8_t keep;
  std::size_t step;
  std::uint8_t* dst;
  std::uint8_t* end;
  // (`ahead` kept records past dst: the lines of at most the next four records there)
  void prefetch(std::size_t ahead, std::size_t lines) const
  {
    prefetchLines(dst, ahead * step, lines);
  }
  template <class Copy>
  void operator()(std::size_t i, const std::uint8_t* src, std::uint8_t* scratch, Copy copy)
  {
    copy(dst != end ? dst : scratch, src);
    // A mask, not `? step : 0`, which GCC made a branch here: it mispredicted at every change
    // between plane and non-plane points.
    dst += step & (std::size_t{0} - (label[i] == keep));
  }
};

// Appended fields of one point (see makeLabelledCloud for the layout); `subset` copies the
// record to a second cloud first (see DenseSubset). `subset` is taken by value: a local whose
// address does not escape, its pointers stay in registers (through a reference, every byte store
// might alias them, and they were reloaded and stored back per point).
template <class Copy, class Subset>
void fillLabelled(const sensor_msgs::PointCloud2& in, const FrameResult& r, std::size_t base, std::size_t step,
                  std::uint8_t* dst, Copy copy, Subset subset)
{
  // Plain pointers: through the vectors the compiler reloads each data pointer per point (the
  // byte stores may alias them).
  const float* const curvature = r.curvature.data();
  const float* const smoothness = r.smoothness.data();
  const float* const discontinuity = r.discontinuity.data();
  const std::int32_t* const primitive = r.primitive.data();
  const std::uint8_t* const label = r.label.data();
  // One record: the input's bytes, then curvature .. primitive as `fields` (16 bytes) and the
  // label, then three zero padding bytes (little-endian).
  const auto record = [&](std::size_t i, const std::uint8_t* src, U32x4 fields) {
    std::uint8_t* const rec = dst + i * step;
    subset(i, src, rec, copy);
    copy.padded(rec, src, base);
    std::uint8_t* const app = rec + base;
    std::memcpy(app, &fields, 16);
    const std::uint32_t last = label[i];
    std::memcpy(app + 16, &last, 4);
  };
  // (a cloud without columns has no points, however many rows it declares)
  const std::uint32_t width = in.width, height = width > 0 ? in.height : 0;
  const std::size_t point_step = in.point_step, row_step = in.row_step;
  const std::uint8_t* const data = in.data.data();
  // Cache lines written per four points (at most, for the subset).
  const std::size_t labelled_lines = (4 * step + kLine - 1) / kLine;
  const std::size_t subset_lines = (4 * point_step + kLine - 1) / kLine;
  std::size_t i = 0;
  for (std::uint32_t row = 0; row < height; ++row)
  {
    const std::uint8_t* src = data + row * row_step;
    std::uint32_t col = 0;
    // Four points at a time: their four 4-byte fields loaded as one vector per field and
    // transposed into one vector per point, one 16-byte store each where there were four 4-byte
    // ones (the loop is bound by its stores). Bit patterns only move: no arithmetic on them.
    for (; col + 4 <= width; col += 4, i += 4, src += 4 * point_step)
    {
      prefetchLines(dst, (i + kStoreAhead) * step, labelled_lines);
      subset.prefetch(kStoreAhead, subset_lines);
      const U32x4 c = loadU32x4(curvature + i), s = loadU32x4(smoothness + i);
      const U32x4 d = loadU32x4(discontinuity + i), p = loadU32x4(primitive + i);
      const U32x4 cs01 = __builtin_shufflevector(c, s, 0, 4, 1, 5), cs23 = __builtin_shufflevector(c, s, 2, 6, 3, 7);
      const U32x4 dp01 = __builtin_shufflevector(d, p, 0, 4, 1, 5), dp23 = __builtin_shufflevector(d, p, 2, 6, 3, 7);
      record(i, src, __builtin_shufflevector(cs01, dp01, 0, 1, 4, 5));
      record(i + 1, src + point_step, __builtin_shufflevector(cs01, dp01, 2, 3, 6, 7));
      record(i + 2, src + 2 * point_step, __builtin_shufflevector(cs23, dp23, 0, 1, 4, 5));
      record(i + 3, src + 3 * point_step, __builtin_shufflevector(cs23, dp23, 2, 3, 6, 7));
    }
    for (; col < width; ++col, ++i, src += point_step)
    {
      std::uint32_t c, s, d, p;
      std::memcpy(&c, curvature + i, 4);
      std::memcpy(&s, smoothness + i, 4);
      std::memcpy(&d, discontinuity + i, 4);
      std::memcpy(&p, primitive + i, 4);
      record(i, src, U32x4{c, s, d, p});
    }
  }
}

// The same without a result (label count does not match the cloud): NaN, -1 and None.
template <class Copy>
void fillUnlabelled(const sensor_msgs::PointCloud2& in, std::size_t base, std::size_t step, std::uint8_t* dst,
                    Copy copy)
{
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const std::int32_t none = -1;
  const std::uint32_t last = 0;  // label None, then the padding
  forEachRecord(in, [&](std::size_t i, const std::uint8_t* src) {
    std::uint8_t* const rec = dst + i * step;
    copy.padded(rec, src, base);
    std::uint8_t* const app = rec + base;
    std::memcpy(app + 0, &nan, 4);
    std::memcpy(app + 4, &nan, 4);
    std::memcpy(app + 8, &nan, 4);
    std::memcpy(app + 12, &none, 4);
    std::memcpy(app + 16, &last, 4);
  });
}

// The top bit of every byte of `x` that is zero, and no other bit: exact per byte, as no sum
// carries from one byte into the next (the classic (x - 1...1) & ~x test's borrow may also mark
// a byte above a zero one).
inline std::uint64_t zeroBytes(std::uint64_t x)
{
  constexpr std::uint64_t lows = 0x7f7f7f7f7f7f7f7full, highs = 0x8080808080808080ull;
  return ~(((x & lows) + lows) | x) & highs;
}

// Number of labels equal to a or b. Counted in blocks with a byte counter: the compiler then
// compares and adds 16 labels per instruction, where a size_t counter made it widen every byte.
std::size_t countLabels(const std::uint8_t* label, std::size_t n, std::uint8_t a, std::uint8_t b)
{
  std::size_t count = 0;
  for (std::size_t first = 0; first < n; first += 255)
  {
    const std::size_t last = std::min(n, first + 255);
    std::uint8_t c = 0;
    for (std::size_t i = first; i < last; ++i)
      c = static_cast<std::uint8_t>(c + ((label[i] == a) | (label[i] == b)));
    count += c;
  }
  return count;
}

// Copies the records of the points labelled `a` or `b`, in order, to `dst` .. `end` (sized for
// exactly those). Dense subsets (the planes are most of a frame) copy every record and advance
// only past kept ones, without a branch per point to mispredict; sparse ones (edges) test first.
template <class Copy>
void copySubset(const sensor_msgs::PointCloud2& in, const std::uint8_t* label, std::uint8_t a, std::uint8_t b,
                bool dense, std::uint8_t* dst, std::uint8_t* const end, Copy copy)
{
  // (a cloud without columns has no points, however many rows it declares)
  const std::uint32_t width = in.width, height = width > 0 ? in.height : 0;
  const std::size_t point_step = in.point_step, row_step = in.row_step;
  const std::uint8_t* const data = in.data.data();
  for (std::uint32_t row = 0; row < height; ++row, label += width)
  {
    const std::uint8_t* const src = data + row * row_step;
    if (dense)
    {
      for (std::uint32_t col = 0; col < width; ++col)
      {
        if (dst == end)  // every kept point copied (and no room for another record)
          return;
        copy(dst, src + col * point_step);
        dst += ((label[col] == a) | (label[col] == b)) ? point_step : 0;
      }
    }
    else
    {
      const auto keep = [&](std::uint32_t col) {
        if (label[col] == a || label[col] == b)
        {
          copy(dst, src + col * point_step);
          dst += point_step;
        }
      };
      // Eight labels at a time, skipped whole when none of them is a or b (most words).
      std::uint32_t col = 0;
      for (; col + 8 <= width; col += 8)
      {
        std::uint64_t w;
        std::memcpy(&w, label + col, 8);
        // One bit per kept label, visited lowest first, which is column order (little-endian):
        // a branch per kept point, where testing each of the eight labels of a word with one
        // mispredicted around every kept point (edges are scattered).
        constexpr std::uint64_t ones = 0x0101010101010101ull;
        std::uint64_t hits = zeroBytes(w ^ (ones * a)) | zeroBytes(w ^ (ones * b));
#if defined(__BYTE_ORDER__) && __BYTE_ORDER__ == __ORDER_LITTLE_ENDIAN__
        for (; hits != 0; hits &= hits - 1)
        {
          const auto k = static_cast<std::uint32_t>(__builtin_ctzll(hits)) / 8;
          copy(dst, src + (col + k) * point_step);
          dst += point_step;
        }
#else
        if (hits != 0)
          for (std::uint32_t k = col; k < col + 8; ++k)
            keep(k);
#endif
      }
      for (; col < width; ++col)
        keep(col);
    }
  }
}

}  // namespace

namespace
{

// Everything of the labelled cloud but its records (sized, not filled). Returns where the
// appended fields start in a record.
std::uint32_t labelledLayout(const sensor_msgs::PointCloud2& input, sensor_msgs::PointCloud2& cloud)
{
  sensor_msgs::PointCloud2* const out = &cloud;
  out->header = input.header;
  out->height = input.height;
  out->width = input.width;
  out->is_bigendian = false;
  out->is_dense = input.is_dense;

  out->fields.clear();
  out->fields.reserve(input.fields.size() + 5);
  for (const auto& f : input.fields)
  {
    out->fields.push_back(f);
    if (isAppendedName(f.name))
      out->fields.back().name = "input_" + f.name;
  }
  // 4-byte alignment for the float/int32 fields; label last so the record pads only once.
  const std::uint32_t base = (input.point_step + 3u) & ~3u;
  out->fields.push_back(field("curvature", base + 0, sensor_msgs::PointField::FLOAT32));
  out->fields.push_back(field("smoothness", base + 4, sensor_msgs::PointField::FLOAT32));
  out->fields.push_back(field("discontinuity", base + 8, sensor_msgs::PointField::FLOAT32));
  out->fields.push_back(field("primitive", base + 12, sensor_msgs::PointField::INT32));
  out->fields.push_back(field("label", base + 16, sensor_msgs::PointField::UINT8));
  out->point_step = base + 20;
  out->row_step = out->point_step * out->width;

  const std::size_t n = static_cast<std::size_t>(input.width) * input.height;
  // Every byte is written below, padding included (zeros): no fill first.
  out->data.resize(n * out->point_step);
  return base;
}

// Everything of a subset cloud (points labelled a or b) but its records (sized, not filled).
// Returns the number of points.
std::size_t subsetLayout(const sensor_msgs::PointCloud2& input, const FrameResult& result, std::uint8_t a,
                         std::uint8_t b, sensor_msgs::PointCloud2& cloud)
{
  sensor_msgs::PointCloud2* const out = &cloud;
  out->header = input.header;
  out->fields = input.fields;
  out->is_bigendian = false;
  // Only valid (finite, in range) returns get a label other than None.
  out->is_dense = true;
  out->point_step = input.point_step;
  out->height = 1;
  const std::size_t count = countLabels(result.label.data(), result.label.size(), a, b);
  out->width = static_cast<std::uint32_t>(count);
  out->row_step = out->width * out->point_step;
  out->data.resize(count * out->point_step);  // every record is copied in below
  return count;
}

}  // namespace

sensor_msgs::PointCloud2Ptr makeLabelledCloud(const sensor_msgs::PointCloud2& input, const FrameResult& result,
                                              sensor_msgs::PointCloud2Ptr reuse)
{
  auto out = recycled(std::move(reuse));
  const std::uint32_t base = labelledLayout(input, *out);
  const std::size_t n = static_cast<std::size_t>(input.width) * input.height;
  // One pass: each input record, then its appended fields.
  std::uint8_t* const dst = out->data.data();
  const std::size_t step = out->point_step;
  withCopier(input.point_step, [&](auto copy) {
    if (result.label.size() == n)
      fillLabelled(input, result, base, step, dst, copy, NoSubset());
    else
      fillUnlabelled(input, base, step, dst, copy);
  });
  return out;
}

sensor_msgs::PointCloud2Ptr makeLabelSubset(const sensor_msgs::PointCloud2& input, const FrameResult& result,
                                            Label a, Label b, sensor_msgs::PointCloud2Ptr reuse)
{
  auto out = recycled(std::move(reuse));
  const auto la = static_cast<std::uint8_t>(a), lb = static_cast<std::uint8_t>(b);
  const std::uint8_t* const label = result.label.data();
  const std::size_t count = subsetLayout(input, result, la, lb, *out);
  if (count > 0)
  {
    std::uint8_t* const dst = out->data.data();
    const bool dense = 4 * count > result.label.size();
    withCopier(input.point_step, [&](auto copy) {
      copySubset(input, label, la, lb, dense, dst, dst + count * input.point_step, copy);
    });
  }
  return out;
}

void makeLabelledAndPlaneClouds(const sensor_msgs::PointCloud2& input, const FrameResult& result,
                                sensor_msgs::PointCloud2Ptr& labelled, sensor_msgs::PointCloud2Ptr& planes)
{
  const std::size_t n = static_cast<std::size_t>(input.width) * input.height;
  if (result.label.size() != n)
  {
    labelled = makeLabelledCloud(input, result, std::move(labelled));
    planes = makeLabelSubset(input, result, Label::Plane, Label::Plane, std::move(planes));
    return;
  }
  labelled = recycled(std::move(labelled));
  planes = recycled(std::move(planes));
  const std::uint32_t base = labelledLayout(input, *labelled);
  const auto plane = static_cast<std::uint8_t>(Label::Plane);
  const std::size_t count = subsetLayout(input, result, plane, plane, *planes);
  std::uint8_t* const dst = planes->data.data();
  const DenseSubset subset{result.label.data(), plane, input.point_step, dst, dst + count * input.point_step};
  withCopier(input.point_step, [&](auto copy) {
    fillLabelled(input, result, base, labelled->point_step, labelled->data.data(), copy, subset);
  });
}

}  // namespace ring_curvature
