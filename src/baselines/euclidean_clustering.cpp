#include "baselines/euclidean_clustering.hpp"

#include <pcl/segmentation/extract_clusters.h>

#include <limits>

namespace ring_curvature
{
namespace baselines
{

EuclideanClustering::EuclideanClustering(const EuclideanClusteringParams& params)
  : params_(params), tree_(new pcl::search::KdTree<pcl::PointXYZ>)
{
}

void EuclideanClustering::label(const PointCloudView& view, std::vector<std::uint8_t>& labels)
{
  const std::size_t n = view.size();
  labels.assign(n, static_cast<std::uint8_t>(Label::None));
  cluster_.assign(n, -1);
  num_clusters_ = 0;
  fillXyzCloud(view, params_.range, xyz_);
  if (xyz_.cloud->points.empty())
    return;

  tree_->setInputCloud(xyz_.cloud);
  pcl::EuclideanClusterExtraction<pcl::PointXYZ> ec;
  ec.setClusterTolerance(params_.tolerance);
  ec.setMinClusterSize(1);  // every valid point gets a cluster, and so a label
  ec.setMaxClusterSize(std::numeric_limits<int>::max());
  ec.setSearchMethod(tree_);
  ec.setInputCloud(xyz_.cloud);
  std::vector<pcl::PointIndices> clusters;
  ec.extract(clusters);

  num_clusters_ = clusters.size();
  for (std::size_t c = 0; c < clusters.size(); ++c)
  {
    const auto size = static_cast<int>(clusters[c].indices.size());
    Label l = Label::Edge;
    if (size >= params_.plane_min_points)
      l = Label::Plane;
    else if (size <= params_.small_max_points)
      l = Label::Rough;
    for (const auto i : clusters[c].indices)
    {
      const std::uint32_t in = xyz_.index[static_cast<std::size_t>(i)];
      labels[in] = static_cast<std::uint8_t>(l);
      cluster_[in] = static_cast<std::int32_t>(c);
    }
  }
}

}  // namespace baselines
}  // namespace ring_curvature
