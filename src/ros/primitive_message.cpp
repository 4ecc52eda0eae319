#include "ring_curvature/ros/primitive_message.hpp"

#include "ring_curvature/ros/geometry_conversions.hpp"
#include "ring_curvature/ros/recycle.hpp"

#include <boost/make_shared.hpp>

#include "ring_curvature/PrimitiveArray.h"

namespace ring_curvature
{


PrimitiveArrayPtr makePrimitiveArray(const std_msgs::Header& header, const PrimitiveSet& set, PrimitiveArrayPtr reuse)
{
  auto out = recycled(std::move(reuse));
  out->header = header;
  // (a recycled array keeps its first primitives and their index buffers: every field of each is
  // set below)
  out->primitives.resize(set.primitives.size());
  for (std::size_t k = 0; k < set.primitives.size(); ++k)
  {
    const PrimitiveInfo& r = set.primitives[k];
    Primitive& m = out->primitives[k];
    m.id = r.id;
    m.label = static_cast<std::uint8_t>(r.label);
    m.num_points = r.num_points;
    m.indices.assign(set.indices.begin() + r.first, set.indices.begin() + r.first + r.num_points);
    m.centroid = toPoint(r.centroid);
    m.axis.x = r.axis.x();
    m.axis.y = r.axis.y();
    m.axis.z = r.axis.z();
    for (int e = 0; e < 3; ++e)
      m.eigenvalues[e] = r.eigenvalues(e);
    const Eigen::Matrix3f& c = r.covariance;  // (the upper triangle, row by row)
    m.covariance = {c(0, 0), c(0, 1), c(0, 2), c(1, 1), c(1, 2), c(2, 2)};
    m.rms_error = r.rms_error;
    m.bbox_min = toPoint(r.bbox_min);
    m.bbox_max = toPoint(r.bbox_max);
    m.ring_min = r.ring_min;
    m.ring_max = r.ring_max;
  }
  return out;
}

}  // namespace ring_curvature
