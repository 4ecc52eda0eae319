// Baseline "Euclidean Clust" of the paper (section 5.3.3): PCL's Euclidean cluster extraction
// followed by size-based labelling, with the same label codes as ours.
#pragma once

#include <pcl/search/kdtree.h>

#include <cstdint>
#include <vector>

#include "baselines/xyz_cloud.hpp"

namespace ring_curvature
{
namespace baselines
{

/// Labelling rule, on the point count of each cluster (the paper names no sizes; these are ours):
///   size >= plane_min_points        -> Plane (1)  (extended structure: ground, walls)
///   small_max_points < size < that  -> Edge  (2)  (compact objects: poles, trunks, cars)
///   size <= small_max_points        -> Rough (4)  (isolated clutter)
///   invalid return                  -> None  (0)
/// Size says nothing about creases or depth jumps, so this baseline never emits Corner (3).
struct EuclideanClusteringParams
{
  float tolerance = 0.2f;        ///< [m] neighbours closer than this join a cluster (0.5 m takes
                                 ///< seconds on dense indoor VLP-16 frames: radius queries return thousands)
  int plane_min_points = 200;    ///< clusters at least this large are Plane
  int small_max_points = 10;     ///< clusters at most this large are Rough
  ValidRange range;
};

class EuclideanClustering
{
public:
  explicit EuclideanClustering(const EuclideanClusteringParams& params = EuclideanClusteringParams());

  /// Labels every input point (view.size() entries, 0 for invalid returns).
  void label(const PointCloudView& view, std::vector<std::uint8_t>& labels);

  /// Cluster of every input point from the last call, -1 for invalid returns.
  const std::vector<std::int32_t>& cluster() const { return cluster_; }
  std::size_t numClusters() const { return num_clusters_; }

private:
  EuclideanClusteringParams params_;
  XyzCloud xyz_;
  pcl::search::KdTree<pcl::PointXYZ>::Ptr tree_;
  std::vector<std::int32_t> cluster_;
  std::size_t num_clusters_ = 0;
};

}  // namespace baselines
}  // namespace ring_curvature
