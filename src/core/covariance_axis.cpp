// One eigenvector of a symmetric 3x3 matrix with Eigen's closed form (see covariance_axis.hpp).
#include "covariance_axis.hpp"

#include <Eigen/Eigenvalues>

#include <utility>

namespace ring_curvature
{

void covarianceAxis(const Eigen::Matrix3d& cov, int which, Eigen::Vector3d& eigenvalues, Eigen::Vector3d& axis)
{
  // Eigen's own building blocks of computeDirect (public static members of its 3x3 solver): the
  // roots of the characteristic polynomial and the kernel of a shifted matrix. The steps around
  // them are computeDirect's, as Eigen 3.4 takes them (test_covariance_axis holds the bits to it):
  using Direct =
      Eigen::internal::direct_selfadjoint_eigenvalues<Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>, 3, false>;
  constexpr double eps = Eigen::NumTraits<double>::epsilon();
  // shifted to the mean eigenvalue and scaled into [-1, 1] (no over- or underflow in the roots)
  const double shift = cov.trace() / 3.0;
  Eigen::Matrix3d scaled = cov.selfadjointView<Eigen::Lower>();
  scaled.diagonal().array() -= shift;
  const double scale = scaled.cwiseAbs().maxCoeff();
  if (scale > 0) scaled /= scale;
  Direct::computeRoots(scaled, eigenvalues);
  axis.setZero();
  if (eigenvalues(2) - eigenvalues(0) <= eps)
    axis(which) = 1.0;  // three equal eigenvalues: computeDirect's identity
  else
  {
    // computeDirect first finds the eigenvector of the eigenvalue farther from the other two (k),
    // from the kernel of the matrix shifted by it. The other end's (l) comes from its own kernel,
    // or, where the two nearer eigenvalues are all but equal, from the first kernel's
    // representative column made orthogonal to k's vector.
    double d0 = eigenvalues(2) - eigenvalues(1);
    const double d1 = eigenvalues(1) - eigenvalues(0);
    int k = 0, l = 2;
    if (d0 > d1)
    {
      std::swap(k, l);
      d0 = d1;
    }
    Eigen::Matrix3d shifted = scaled;
    Eigen::Vector3d other;
    if (which == k)
    {
      shifted.diagonal().array() -= eigenvalues(k);
      Direct::extract_kernel(shifted, axis, other);
    }
    else if (d0 <= 2 * eps * d1)
    {
      shifted.diagonal().array() -= eigenvalues(k);
      Direct::extract_kernel(shifted, other, axis);  // axis: the representative column
      axis -= other.dot(axis) * axis;  // (computeDirect's expression, as it stands)
      axis.normalize();
    }
    else
    {
      shifted.diagonal().array() -= eigenvalues(l);
      Direct::extract_kernel(shifted, axis, other);
    }
  }
  eigenvalues *= scale;
  eigenvalues.array() += shift;
}

}  // namespace ring_curvature
