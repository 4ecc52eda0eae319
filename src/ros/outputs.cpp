#include "ring_curvature/ros/outputs.hpp"

#include <sensor_msgs/PointField.h>

#include <boost/make_shared.hpp>
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

// Copies one record of `n` bytes. Records are small (22 bytes for a velodyne XYZIRT, 48 for an
// ouster point) and a memcpy call per record with a run-time size was the largest cost of the
// output messages: whole 8-byte words instead, the last one overlapping its predecessor.
inline void copyRecord(std::uint8_t* dst, const std::uint8_t* src, std::size_t n)
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

// Calls f(i, record) for every input point in order, walking rows and columns: a division and
// a modulo per point (to find its row) cost more than the rest of the copy.
template <class F>
void forEachRecord(const sensor_msgs::PointCloud2& in, F f)
{
  std::size_t i = 0;
  for (std::uint32_t row = 0; row < in.height; ++row)
  {
    const std::uint8_t* src = in.data.data() + static_cast<std::size_t>(row) * in.row_step;
    for (std::uint32_t col = 0; col < in.width; ++col, ++i, src += in.point_step)
      f(i, src);
  }
}

// Copies the input records of the points for which keep(i) holds, in order, into `out`
// (already sized). Records are copied whole so that every input field survives.
template <class Keep>
void copyRecords(const sensor_msgs::PointCloud2& in, std::uint32_t out_step, std::uint8_t* out, Keep keep)
{
  std::uint8_t* dst = out;
  forEachRecord(in, [&](std::size_t i, const std::uint8_t* src) {
    if (!keep(i))
      return;
    copyRecord(dst, src, in.point_step);
    dst += out_step;
  });
}

}  // namespace

sensor_msgs::PointCloud2Ptr makeLabelledCloud(const sensor_msgs::PointCloud2& input, const FrameResult& result)
{
  auto out = boost::make_shared<sensor_msgs::PointCloud2>();
  out->header = input.header;
  out->height = input.height;
  out->width = input.width;
  out->is_bigendian = false;
  out->is_dense = input.is_dense;

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
  // Zero-filled, so padding bytes are deterministic.
  out->data.assign(n * out->point_step, 0);
  // One pass: each input record, then its appended fields.
  std::uint8_t* const dst = out->data.data();
  const std::uint32_t step = out->point_step;
  const bool have = result.label.size() == n;
  forEachRecord(input, [&](std::size_t i, const std::uint8_t* src) {
    std::uint8_t* const rec = dst + i * step;
    copyRecord(rec, src, input.point_step);
    std::uint8_t* const app = rec + base;
    const float c = have ? result.curvature[i] : std::numeric_limits<float>::quiet_NaN();
    const float s = have ? result.smoothness[i] : std::numeric_limits<float>::quiet_NaN();
    const float d = have ? result.discontinuity[i] : std::numeric_limits<float>::quiet_NaN();
    const std::int32_t p = have ? result.primitive[i] : -1;
    const std::uint8_t l = have ? result.label[i] : 0;
    std::memcpy(app + 0, &c, 4);
    std::memcpy(app + 4, &s, 4);
    std::memcpy(app + 8, &d, 4);
    std::memcpy(app + 12, &p, 4);
    app[16] = l;
  });
  return out;
}

sensor_msgs::PointCloud2Ptr makeLabelSubset(const sensor_msgs::PointCloud2& input, const FrameResult& result,
                                            Label a, Label b)
{
  auto out = boost::make_shared<sensor_msgs::PointCloud2>();
  out->header = input.header;
  out->fields = input.fields;
  out->is_bigendian = false;
  // Only valid (finite, in range) returns get a label other than None.
  out->is_dense = true;
  out->point_step = input.point_step;
  out->height = 1;

  const auto la = static_cast<std::uint8_t>(a), lb = static_cast<std::uint8_t>(b);
  const auto keep = [&](std::size_t i) { return result.label[i] == la || result.label[i] == lb; };
  std::size_t count = 0;
  const std::uint8_t* const label = result.label.data();
  for (std::size_t i = 0; i < result.label.size(); ++i)
    count += (label[i] == la) | (label[i] == lb) ? 1u : 0u;
  out->width = static_cast<std::uint32_t>(count);
  out->row_step = out->width * out->point_step;
  out->data.resize(count * out->point_step);
  if (count > 0)
    copyRecords(input, out->point_step, out->data.data(), keep);
  return out;
}

}  // namespace ring_curvature
