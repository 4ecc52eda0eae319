#include "baselines/xyz_cloud.hpp"

#include <cmath>

namespace ring_curvature
{
namespace baselines
{

namespace
{
float readCoordinate(const std::uint8_t* rec, const FieldView& f)
{
  // Float32 is the common case; other types go through the core's generic reader.
  return f.type == ScalarType::Float32 ? readFloat32(rec + f.offset)
                                       : static_cast<float>(readScalar(rec + f.offset, f.type));
}
}  // namespace

void fillXyzCloud(const PointCloudView& view, const ValidRange& range, XyzCloud& out)
{
  auto& pts = out.cloud->points;
  pts.clear();
  out.index.clear();
  const std::size_t n = view.size();
  if (view.data == nullptr || !view.x.present() || !view.y.present() || !view.z.present())
  {
    out.cloud->width = 0;
    out.cloud->height = 1;
    return;
  }
  pts.reserve(n);
  out.index.reserve(n);
  const float min2 = range.min_range * range.min_range;
  const float max2 = range.max_range * range.max_range;
  for (std::size_t i = 0; i < n; ++i)
  {
    const std::uint8_t* rec = view.record(i);
    const float x = readCoordinate(rec, view.x);
    const float y = readCoordinate(rec, view.y);
    const float z = readCoordinate(rec, view.z);
    const float r2 = x * x + y * y + z * z;
    // NaN fails both comparisons, so non-finite returns are dropped here too.
    if (!(r2 >= min2 && r2 <= max2))
      continue;
    pts.emplace_back(x, y, z);
    out.index.push_back(static_cast<std::uint32_t>(i));
  }
  out.cloud->width = static_cast<std::uint32_t>(pts.size());
  out.cloud->height = 1;
  out.cloud->is_dense = true;  // every kept point is finite
}

}  // namespace baselines
}  // namespace ring_curvature
