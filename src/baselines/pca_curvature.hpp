// Baseline "PCA-Curv" of the paper (section 5.3.3): PCL's covariance curvature over k nearest
// neighbours, thresholded into labels with the same codes as ours.
#pragma once

#include <pcl/features/normal_3d.h>
#include <pcl/search/kdtree.h>

#include <cstdint>
#include <vector>

#include "baselines/xyz_cloud.hpp"

namespace ring_curvature
{
namespace baselines
{

/// Labelling rule, on PCL's surface variation sigma = l0 / (l0 + l1 + l2) in [0, 1/3]
/// (l0 <= l1 <= l2, eigenvalues of the k-neighbour covariance):
///   sigma <  plane_max              -> Plane (1)
///   plane_max <= sigma < rough_min  -> Edge  (2)  (a crease bends the neighbourhood moderately)
///   sigma >= rough_min              -> Rough (4)  (near-isotropic scatter: clutter, vegetation)
///   invalid return / NaN sigma      -> None  (0)
/// PCA alone cannot tell a crease from a depth jump, so this baseline never emits Corner (3).
struct PcaCurvatureParams
{
  int k = 10;               ///< neighbours per point (the paper's and ENVIRONMENT.md's k)
  float plane_max = 0.02f;  ///< sigma below this is Plane
  float rough_min = 0.10f;  ///< sigma at or above this is Rough
  ValidRange range;
};

class PcaCurvature
{
public:
  explicit PcaCurvature(const PcaCurvatureParams& params = PcaCurvatureParams());

  /// Labels every input point (view.size() entries, 0 for invalid returns).
  void label(const PointCloudView& view, std::vector<std::uint8_t>& labels);

  /// sigma of every input point from the last call (NaN for invalid returns).
  const std::vector<float>& curvature() const { return curvature_; }

private:
  PcaCurvatureParams params_;
  XyzCloud xyz_;
  pcl::search::KdTree<pcl::PointXYZ>::Ptr tree_;
  pcl::NormalEstimation<pcl::PointXYZ, pcl::Normal> estimator_;
  pcl::PointCloud<pcl::Normal> normals_;
  std::vector<float> curvature_;
};

}  // namespace baselines
}  // namespace ring_curvature
