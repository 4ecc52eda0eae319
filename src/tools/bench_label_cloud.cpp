#include "bench_label_cloud.hpp"

#include <cstring>

namespace ring_curvature
{
namespace bench
{

void appendLabelField(const sensor_msgs::PointCloud2& in, const std::vector<std::uint8_t>& labels,
                      sensor_msgs::PointCloud2& out)
{
  out.header = in.header;
  out.height = in.height;
  out.width = in.width;
  out.is_bigendian = in.is_bigendian;
  out.is_dense = in.is_dense;
  out.fields.clear();
  std::uint32_t label_offset = in.point_step;
  for (const auto& f : in.fields)
  {
    if (f.name == "label")
      label_offset = f.offset;  // overwrite in place rather than carry two `label` fields
    else
      out.fields.push_back(f);
  }
  const bool append = label_offset == in.point_step;
  sensor_msgs::PointField lf;
  lf.name = "label";
  lf.offset = label_offset;
  lf.datatype = sensor_msgs::PointField::UINT8;
  lf.count = 1;
  out.fields.push_back(lf);
  out.point_step = in.point_step + (append ? 1u : 0u);
  out.row_step = out.point_step * out.width;
  out.data.assign(static_cast<std::size_t>(out.row_step) * out.height, 0);
  for (std::uint32_t r = 0; r < in.height; ++r)
  {
    for (std::uint32_t c = 0; c < in.width; ++c)
    {
      const std::size_t i = static_cast<std::size_t>(r) * in.width + c;
      const std::uint8_t* src = &in.data[r * static_cast<std::size_t>(in.row_step) + c * in.point_step];
      std::uint8_t* dst = &out.data[r * static_cast<std::size_t>(out.row_step) + c * out.point_step];
      std::memcpy(dst, src, in.point_step);
      dst[label_offset] = i < labels.size() ? labels[i] : 0;
    }
  }
}

}  // namespace bench
}  // namespace ring_curvature
