// The eigenvalues of a primitive's 3x3 covariance and the one eigenvector the primitive reports
// (PrimitiveExtractor::extract): the characteristic cubic's extreme root by a seeded Newton step,
// the other two from the deflated quadratic, the eigenvector from a kernel as Eigen extracts it.
#pragma once

#include <Eigen/Core>

namespace ring_curvature
{

/// Eigenvalues of the symmetric `cov` (lower triangle read), ascending, and the unit eigenvector of
/// eigenvalue `which` (0: smallest, a plane's normal; 2: largest, an edge's direction; not 1): the
/// steps of Eigen's SelfAdjointEigenSolver::computeDirect without its trigonometric closed form, a
/// close pair found again from the matrix. Last bits differ, accuracy is no less (see
/// test_covariance_axis); the sign is computeDirect's but where its kernel choice is a near tie.
void covarianceAxis(const Eigen::Matrix3d& cov, int which, Eigen::Vector3d& eigenvalues, Eigen::Vector3d& axis);

namespace detail
{
/// The Newton step's seed: c^0 ... c^8 coefficients of the degree-8 Chebyshev interpolant of
/// 2 cos(acos(c) / 3) (largest root of t^3 - 3 t = 2 c) on [0, 1], where it is smooth (singular at
/// c = -1); test_covariance_axis recomputes them and bounds the seed's error (<= 3.7e-9).
constexpr double kCubicSeed[9] = {1.7320508111991304,     0.3333327422889974,     -0.09620888290586746,
                                  0.049208593584660107,   -0.030214550322435859,  0.018766661141408167,
                                  -0.0098593823448516194, 0.0035297137462267925,  -0.00060570840289964067};

/// That root for c in [0, 1]: the seed in Estrin's form (a short dependency chain), then one Newton
/// step (|f'| = 3 t^2 - 3 >= 6 there, so it squares the seed's error to below t's own rounding).
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
