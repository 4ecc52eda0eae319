#include "ring_curvature/ros/loam_outputs.hpp"

#include <sensor_msgs/PointField.h>

#include "ring_curvature/ros/recycle.hpp"

#include <cstring>

namespace ring_curvature
{

namespace
{
sensor_msgs::PointField floatField(const char* name, std::uint32_t offset)
{
  sensor_msgs::PointField f;
  f.name = name;
  f.offset = offset;
  f.datatype = sensor_msgs::PointField::FLOAT32;
  f.count = 1;
  return f;
}
}  // namespace

sensor_msgs::PointCloud2Ptr makeLoamCloud(const sensor_msgs::PointCloud2& input, const ScanGrid& grid,
                                          const LoamFeatures& features, const std::vector<std::uint32_t>* positions,
                                          LoamPointFormat format, sensor_msgs::PointCloud2Ptr reuse,
                                          const SweepDeskew* deskew)
{
  auto out = recycled(std::move(reuse));
  const std::size_t n = positions ? positions->size() : grid.size();
  const auto at = [&](std::size_t i) { return positions ? (*positions)[i] : static_cast<std::uint32_t>(i); };
  out->header = input.header;
  out->height = 1;
  out->width = static_cast<std::uint32_t>(n);
  out->is_bigendian = false;
  out->is_dense = true;  // grid points are finite returns
  if (format == LoamPointFormat::Input)
  {
    out->fields = input.fields;
    out->point_step = input.point_step;
    out->row_step = static_cast<std::uint32_t>(n * input.point_step);
    out->data.resize(n * input.point_step);
    const std::size_t ps = input.point_step;
    for (std::size_t i = 0; i < n; ++i)
    {
      const std::uint32_t idx = grid.index[at(i)];
      const std::size_t row = idx / input.width, col = idx % input.width;
      std::memcpy(&out->data[i * ps], &input.data[row * input.row_step + col * ps], ps);
    }
    return out;
  }
  if (out->fields.size() != 4)
    out->fields = {floatField("x", 0), floatField("y", 4), floatField("z", 8), floatField("intensity", kXyziIntensityOffset)};
  out->point_step = kXyziPointStep;
  out->row_step = static_cast<std::uint32_t>(n * kXyziPointStep);
  out->data.resize(n * kXyziPointStep);
  RingCursor ring{grid};
  for (std::size_t i = 0; i < n; ++i)
  {
    const std::uint32_t p = at(i);
    float rec[8] = {static_cast<float>(grid.x[p]), static_cast<float>(grid.y[p]), static_cast<float>(grid.z[p]), 1.0f,
                    static_cast<float>(ring(p)) + features.sweep_time[p], 0.0f, 0.0f, 0.0f};
    if (deskew) deskew->apply(features.sweep_time[p], rec[0], rec[1], rec[2]);
    std::memcpy(&out->data[i * kXyziPointStep], rec, sizeof rec);
  }
  return out;
}

}  // namespace ring_curvature
