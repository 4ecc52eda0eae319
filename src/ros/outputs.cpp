// The labelled cloud (~labelled_points): every input record followed by the per-point results;
// and, in the same pass, the plane cloud (the other subsets: label_subsets.cpp).

#include "ring_curvature/ros/outputs.hpp"

#include <sensor_msgs/PointField.h>

#include "label_subsets.hpp"
#include "record_copy.hpp"
#include "ring_curvature/prefetch.hpp"
#include "ring_curvature/ros/recycle.hpp"

#include <boost/make_shared.hpp>
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

// Calls f(i, record) for every input point in order, walking rows and columns (no division per
// point to find its row); the sizes are read once, as the callers' byte stores may alias them.
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

// The output clouds are written to lines in no cache (a recycled buffer was last written a frame
// ago, a new one never), so each store would wait for its line and the store buffer would fill:
// the lines kStoreAhead points ahead are asked for while the current ones are written.
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

// The records labelled `keep`, copied in order to dst .. end while fillLabelled walks the input
// (each record read once for both clouds): every record copied, the pointer advanced past kept
// ones only (no branch); once all are in, into the labelled record next written (`scratch`).
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

// Appended fields of one point (see makeLabelledCloud for the layout); `subset` copies the record
// to a second cloud first, taken by value so that its pointers stay in registers (through a
// reference, every byte store might alias them).
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
  detail::withCopier(input.point_step, [&](auto copy) {
    if (result.label.size() == n)
      fillLabelled(input, result, base, step, dst, copy, NoSubset());
    else
      fillUnlabelled(input, base, step, dst, copy);
  });
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
  const std::size_t count = detail::subsetLayout(input, result, plane, plane, *planes);
  std::uint8_t* const dst = planes->data.data();
  const DenseSubset subset{result.label.data(), plane, input.point_step, dst, dst + count * input.point_step};
  detail::withCopier(input.point_step, [&](auto copy) {
    fillLabelled(input, result, base, labelled->point_step, labelled->data.data(), copy, subset);
  });
}

}  // namespace ring_curvature
