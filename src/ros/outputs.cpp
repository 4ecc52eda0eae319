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

// Copies the input records of the points for which keep(i) holds, in order, into `out`
// (already sized). Records are copied whole so that every input field survives.
template <class Keep>
void copyRecords(const sensor_msgs::PointCloud2& in, std::uint32_t out_step, std::uint8_t* out, Keep keep)
{
  const std::size_t n = static_cast<std::size_t>(in.width) * in.height;
  std::size_t j = 0;
  for (std::size_t i = 0; i < n; ++i)
  {
    if (!keep(i))
      continue;
    const std::uint8_t* src = in.data.data() + (i / in.width) * static_cast<std::size_t>(in.row_step) +
                              (i % in.width) * static_cast<std::size_t>(in.point_step);
    std::memcpy(out + j * out_step, src, in.point_step);
    ++j;
  }
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
  std::uint8_t* dst = out->data.data();
  copyRecords(input, out->point_step, dst, [](std::size_t) { return true; });

  const bool have = result.label.size() == n;
  for (std::size_t i = 0; i < n; ++i)
  {
    std::uint8_t* rec = dst + i * out->point_step + base;
    const float c = have ? result.curvature[i] : std::numeric_limits<float>::quiet_NaN();
    const float s = have ? result.smoothness[i] : std::numeric_limits<float>::quiet_NaN();
    const float d = have ? result.discontinuity[i] : std::numeric_limits<float>::quiet_NaN();
    const std::int32_t p = have ? result.primitive[i] : -1;
    const std::uint8_t l = have ? result.label[i] : 0;
    std::memcpy(rec + 0, &c, 4);
    std::memcpy(rec + 4, &s, 4);
    std::memcpy(rec + 8, &d, 4);
    std::memcpy(rec + 12, &p, 4);
    rec[16] = l;
  }
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
  for (std::size_t i = 0; i < result.label.size(); ++i)
    count += keep(i) ? 1u : 0u;
  out->width = static_cast<std::uint32_t>(count);
  out->row_step = out->width * out->point_step;
  out->data.resize(count * out->point_step);
  if (count > 0)
    copyRecords(input, out->point_step, out->data.data(), keep);
  return out;
}

}  // namespace ring_curvature
