// Section 4.3: connected components of same-label neighbours on the scan grid (union-find,
// linear time) and a geometric summary of each component.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <vector>

#include "ring_curvature/features.hpp"

namespace ring_curvature
{

/// One primitive. (Named PrimitiveInfo because the message msg/Primitive.msg generates
/// ring_curvature::Primitive, and a user may include both.)
struct PrimitiveInfo
{
  std::uint32_t id = 0;           ///< index in PrimitiveSet::primitives
  Label label = Label::None;
  std::uint32_t num_points = 0;
  std::uint32_t first = 0;        ///< offset of its indices in PrimitiveSet::indices
  Eigen::Vector3f centroid = Eigen::Vector3f::Zero();
  Eigen::Vector3f axis = Eigen::Vector3f::Zero();         ///< PLANE: unit normal; else principal direction
  Eigen::Vector3f eigenvalues = Eigen::Vector3f::Zero();  ///< covariance eigenvalues, ascending [m^2]
  /// covariance of the points (duplicates included) about their mean, divided by num_points
  /// [m^2]: what `eigenvalues` and `axis` come from, e.g. for a SLAM factor's weight or a
  /// patch's in-plane extent
  Eigen::Matrix3f covariance = Eigen::Matrix3f::Zero();
  Eigen::Vector3f bbox_min = Eigen::Vector3f::Zero(), bbox_max = Eigen::Vector3f::Zero();
  float rms_error = 0;            ///< PLANE: RMS distance to the plane; EDGE: to the line [m]
  std::uint16_t ring_min = 0, ring_max = 0;
};

struct PrimitiveSet
{
  std::vector<PrimitiveInfo> primitives;
  std::vector<std::uint32_t> indices;       ///< input point indices, grouped per primitive
  std::vector<std::int32_t> of_grid;        ///< primitive id of each grid position, -1 if none
  void clear() { primitives.clear(); indices.clear(); of_grid.clear(); }
};

}  // namespace ring_curvature
