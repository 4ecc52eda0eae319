#include "baselines/pca_curvature.hpp"

#include <cmath>
#include <limits>

namespace ring_curvature
{
namespace baselines
{

PcaCurvature::PcaCurvature(const PcaCurvatureParams& params)
  : params_(params), tree_(new pcl::search::KdTree<pcl::PointXYZ>)
{
  estimator_.setSearchMethod(tree_);
  estimator_.setKSearch(params_.k);
}

void PcaCurvature::label(const PointCloudView& view, std::vector<std::uint8_t>& labels)
{
  const std::size_t n = view.size();
  labels.assign(n, static_cast<std::uint8_t>(Label::None));
  curvature_.assign(n, std::numeric_limits<float>::quiet_NaN());
  fillXyzCloud(view, params_.range, xyz_);
  if (xyz_.cloud->points.size() <= static_cast<std::size_t>(params_.k))
    return;  // too few points for one neighbourhood: nothing to label

  // The kd-tree build is part of the method's cost, as it is in PCL's own pipeline.
  estimator_.setInputCloud(xyz_.cloud);
  estimator_.compute(normals_);

  for (std::size_t i = 0; i < xyz_.index.size(); ++i)
  {
    const float sigma = normals_.points[i].curvature;
    const std::uint32_t in = xyz_.index[i];
    curvature_[in] = sigma;
    if (!std::isfinite(sigma))
      continue;
    Label l = Label::Plane;
    if (sigma >= params_.rough_min)
      l = Label::Rough;
    else if (sigma >= params_.plane_max)
      l = Label::Edge;
    labels[in] = static_cast<std::uint8_t>(l);
  }
}

}  // namespace baselines
}  // namespace ring_curvature
