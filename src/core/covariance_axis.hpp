// The eigenvalues of a primitive's 3x3 covariance and the one eigenvector the primitive reports
// (PrimitiveExtractor::extract): the characteristic cubic's extreme root by a seeded Newton step,
// the other two from the deflated quadratic, the eigenvector from a kernel as Eigen extracts it.
#pragma once

#include <Eigen/Core>

namespace ring_curvature
{

/// Eigenvalues of the symmetric matrix `cov` (only its lower triangle is read), ascending, and
/// the unit eigenvector of eigenvalue `which` (0: the smallest, a plane's normal; 2: the largest,
/// an edge's direction; 1 is not offered). The steps of Eigen's SelfAdjointEigenSolver::
/// computeDirect (shift by the mean eigenvalue, scale, roots of the characteristic cubic, the
/// kernel of the matrix shifted by the eigenvalue, with its choice of column and sign) but
/// without its trigonometric closed form (atan2, cos and sin were 40 % of the solve), and with a
/// close pair of eigenvalues found again from the matrix: the results differ from
/// computeDirect's in their last bits, and are no less accurate (test_covariance_axis measures
/// both against a long-double solver: for close pairs far more); the vector has computeDirect's
/// sign but where its kernel choice is a near tie.
void covarianceAxis(const Eigen::Matrix3d& cov, int which, Eigen::Vector3d& eigenvalues, Eigen::Vector3d& axis);

}  // namespace ring_curvature
