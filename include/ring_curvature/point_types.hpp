// PCL point type of ~labelled_points for Velodyne input (velodyne_pointcloud's XYZIRT plus the
// fields ring_curvature appends), so a user can pcl::fromROSMsg the labelled cloud:
//
//   pcl::PointCloud<ring_curvature::PointXYZIRTLabelled> cloud;
//   pcl::fromROSMsg(*msg, cloud);   // fields are matched by name and datatype
//
// For other drivers' layouts, declare the driver's fields the same way plus the five below.
// Header-only; this package's libraries do not depend on PCL.
#pragma once

#define PCL_NO_PRECOMPILE
#include <pcl/point_types.h>
#include <pcl/register_point_struct.h>

#include <cstdint>

namespace ring_curvature
{

struct EIGEN_ALIGN16 PointXYZIRTLabelled
{
  PCL_ADD_POINT4D;                 // x, y, z (+ padding)
  float intensity;
  std::uint16_t ring;
  float time;                      // [s] after the header stamp
  float curvature;                 // discrete geodesic curvature [1/m], NaN where undefined
  float smoothness;                // S [m^2]
  float discontinuity;             // D
  std::int32_t primitive;          // index into the PrimitiveArray of the same stamp, -1 for none
  std::uint8_t label;              // 0 none, 1 plane, 2 edge, 3 corner, 4 rough
  PCL_MAKE_ALIGNED_OPERATOR_NEW
};

}  // namespace ring_curvature

POINT_CLOUD_REGISTER_POINT_STRUCT(ring_curvature::PointXYZIRTLabelled,
                                  (float, x, x)(float, y, y)(float, z, z)(float, intensity, intensity)
                                  (std::uint16_t, ring, ring)(float, time, time)(float, curvature, curvature)
                                  (float, smoothness, smoothness)(float, discontinuity, discontinuity)
                                  (std::int32_t, primitive, primitive)(std::uint8_t, label, label))
