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

namespace detail
{
/// The seed of covarianceAxis' Newton step: the coefficients of c^0 ... c^8 of the degree-8
/// Chebyshev interpolant of 2 cos(acos(c) / 3) (the largest root t of t^3 - 3 t = 2 c) on
/// c in [0, 1], at the 9 Chebyshev nodes of that interval, expanded into powers of c in long
/// double and rounded to double (the root is smooth on [0, 1]: its nearest singularity is the
/// double root at c = -1). test_covariance_axis computes them again that way and holds
/// these to it, and measures the seed's error (<= 3.7e-9) and the error after the step.
constexpr double kCubicSeed[9] = {1.7320508111991304,     0.3333327422889974,     -0.09620888290586746,
                                  0.049208593584660107,   -0.030214550322435859,  0.018766661141408167,
                                  -0.0098593823448516194, 0.0035297137462267925,  -0.00060570840289964067};

/// That root for c in [0, 1]: the seed in Estrin's form (a short dependency chain), then one
/// Newton step on the cubic (|f'| = 3 t^2 - 3 >= 6 there, so the step squares the seed's error
/// to below the rounding of t itself; a second step changed nothing). (atan2, cos and sin in
/// computeDirect's closed form cost more.)
inline double cubicRoot(double c)
{
  const double* const k = kCubicSeed;
  const double c2 = c * c, c4 = c2 * c2;
  const double p01 = k[0] + k[1] * c, p23 = k[2] + k[3] * c, p45 = k[4] + k[5] * c, p67 = k[6] + k[7] * c;
  double t = (p01 + c2 * p23) + c4 * ((p45 + c2 * p67) + c4 * k[8]);
  const double t2 = t * t;
  t -= (t * (t2 - 3.0) - 2.0 * c) / (3.0 * (t2 - 1.0));
  return t;
}
}  // namespace detail

}  // namespace ring_curvature
