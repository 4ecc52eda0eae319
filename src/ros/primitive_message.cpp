#include "ring_curvature/ros/primitive_message.hpp"

#include <boost/make_shared.hpp>

#include "ring_curvature/PrimitiveArray.h"

namespace ring_curvature
{

namespace
{
geometry_msgs::Point toPoint(const float v[3])
{
  geometry_msgs::Point p;
  p.x = v[0];
  p.y = v[1];
  p.z = v[2];
  return p;
}
}  // namespace

PrimitiveArrayPtr makePrimitiveArray(const std_msgs::Header& header, const std::vector<PrimitiveRecord>& records,
                                     const std::vector<std::uint32_t>& indices)
{
  auto out = boost::make_shared<PrimitiveArray>();
  out->header = header;
  out->primitives.resize(records.size());
  for (std::size_t k = 0; k < records.size(); ++k)
  {
    const PrimitiveRecord& r = records[k];
    Primitive& m = out->primitives[k];
    m.id = r.id;
    m.label = r.label;
    m.num_points = r.num_points;
    m.indices.assign(indices.begin() + r.first, indices.begin() + r.first + r.num_points);
    m.centroid = toPoint(r.centroid);
    m.axis.x = r.axis[0];
    m.axis.y = r.axis[1];
    m.axis.z = r.axis[2];
    for (int e = 0; e < 3; ++e)
      m.eigenvalues[e] = r.eigenvalues[e];
    m.rms_error = r.rms_error;
    m.bbox_min = toPoint(r.bbox_min);
    m.bbox_max = toPoint(r.bbox_max);
    m.ring_min = r.ring_min;
    m.ring_max = r.ring_max;
  }
  return out;
}

}  // namespace ring_curvature
