// The eigenvalues of a primitive's 3x3 covariance and the one eigenvector the primitive reports
// (PrimitiveExtractor::extract), the bits of Eigen's SelfAdjointEigenSolver::computeDirect.
#pragma once

#include <Eigen/Core>

namespace ring_curvature
{

/// Eigenvalues of the symmetric matrix `cov` (only its lower triangle is read), ascending, and
/// the unit eigenvector of eigenvalue `which` (0: the smallest, a plane's normal; 2: the largest,
/// an edge's direction): exactly SelfAdjointEigenSolver<Matrix3d>::computeDirect(cov)'s
/// eigenvalues() and eigenvectors().col(which), bit for bit, sign included. It takes the same
/// steps with Eigen's own closed-form roots and kernel extraction, but only for the column
/// asked for: computeDirect finds all three (two kernels, a cross product, three
/// normalisations), and it was 7 % of a VLP-16 frame's pipeline for ~350 primitives.
void covarianceAxis(const Eigen::Matrix3d& cov, int which, Eigen::Vector3d& eigenvalues, Eigen::Vector3d& axis);

}  // namespace ring_curvature
