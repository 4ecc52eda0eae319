// One eigenvector of a symmetric 3x3 matrix, trigonometry-free (see covariance_axis.hpp).
#include "primitives/covariance_axis.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>

namespace ring_curvature
{
namespace
{
constexpr double kEps = 2.220446049250313e-16;  // (Eigen's NumTraits<double>::epsilon())
// Half the pair's gap over sqrt(a) (h below) under which its eigenvalues are found again from the
// matrix: the quadratic's gap from q keeps fewer than ~28 of its bits there. Where h is 0 (a pair
// equal to about sqrt(eps), as two points' rank-one covariance) it stays equal, as in computeDirect.
constexpr double kClosePair = 1.0 / 4096;

// Eigen's extract_kernel on the singular symmetric m: the cross products of m's column of largest
// diagonal magnitude (first of equals) with the other two, the longer normalised. Its choice, not
// the longest of all three, keeps computeDirect's sign. Returns that column (`representative`).
inline int extractKernel(const double m[3][3], Eigen::Vector3d& v)
{
  int i0 = 0;
  double d = std::abs(m[0][0]);
  if (std::abs(m[1][1]) > d) d = std::abs(m[1][1]), i0 = 1;
  if (std::abs(m[2][2]) > d) i0 = 2;
  const double* r = m[i0];  // (rows are columns: m is symmetric)
  const double* s1 = m[(i0 + 1) % 3];
  const double* s2 = m[(i0 + 2) % 3];
  const double a0 = r[1] * s1[2] - r[2] * s1[1], a1 = r[2] * s1[0] - r[0] * s1[2], a2 = r[0] * s1[1] - r[1] * s1[0];
  const double b0 = r[1] * s2[2] - r[2] * s2[1], b1 = r[2] * s2[0] - r[0] * s2[2], b2 = r[0] * s2[1] - r[1] * s2[0];
  const double n0 = a0 * a0 + a1 * a1 + a2 * a2, n1 = b0 * b0 + b1 * b1 + b2 * b2;
  if (n0 > n1)
  {
    const double l = std::sqrt(n0);
    v = Eigen::Vector3d(a0 / l, a1 / l, a2 / l);
  }
  else
  {
    const double l = std::sqrt(n1);
    v = Eigen::Vector3d(b0 / l, b1 / l, b2 / l);
  }
  return i0;
}

// m - lambda I
inline void shifted(const double m[3][3], double lambda, double out[3][3])
{
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) out[i][j] = m[i][j];
  out[0][0] -= lambda, out[1][1] -= lambda, out[2][2] -= lambda;
}

// cov shifted to its mean eigenvalue (as computeDirect), scaled by a power of two to put the largest
// magnitude in [1, 2): exact (computeDirect's division rounds). False for a multiple of identity.
bool scaledShifted(const Eigen::Matrix3d& cov, double m[3][3], double& shift, double& up)
{
  shift = (cov(0, 0) + cov(1, 1) + cov(2, 2)) / 3.0;
  const double e00 = cov(0, 0) - shift, e11 = cov(1, 1) - shift, e22 = cov(2, 2) - shift;
  const double e10 = cov(1, 0), e20 = cov(2, 0), e21 = cov(2, 1);
  const double big = std::max(std::max(std::max(std::abs(e00), std::abs(e11)), std::max(std::abs(e22), std::abs(e10))),
                              std::max(std::abs(e20), std::abs(e21)));
  if (!(big > 0)) return false;
  std::uint64_t bits;
  std::memcpy(&bits, &big, sizeof bits);
  // the biased exponent, kept where both powers are normal numbers (subnormal covariances scale
  // into [2^-52, 1), the largest ones into [2, 4): no over- or underflow either way)
  const std::uint64_t e = std::min<std::uint64_t>(std::max<std::uint64_t>(bits >> 52, 1), 2045);
  double down;
  bits = (2046 - e) << 52;
  std::memcpy(&down, &bits, sizeof down);
  bits = e << 52;
  std::memcpy(&up, &bits, sizeof up);
  m[0][0] = e00 * down, m[1][1] = e11 * down, m[2][2] = e22 * down;
  m[1][0] = m[0][1] = e10 * down, m[2][0] = m[0][2] = e20 * down, m[2][1] = m[1][2] = e21 * down;
  return true;
}

// The scaled matrix's eigenvalues, ascending, and the terms the close pair's refinement reuses.
struct CubicRoots
{
  double l0, l1, l2;
  double c2_3, rho, half, h;
  bool top;  // the largest eigenvalue is the one apart (else the smallest)
};

CubicRoots cubicRoots(const double m[3][3])
{
  // The characteristic cubic as computeRoots forms it, depressed (y = x - c2 / 3) to y^3 - 3 a y - 2 b,
  // roots 2 sqrt(a) t for t^3 - 3 t = 2 c, c = b / a^1.5 in [-1, 1]. The root of largest magnitude is
  // farthest from the others (they sum to zero), so simple and well conditioned: the largest where
  // c >= 0, else the smallest (-(the largest root for -c)).
  const double c0 = m[0][0] * m[1][1] * m[2][2] + 2.0 * m[1][0] * m[2][0] * m[2][1] - m[0][0] * m[2][1] * m[2][1] -
                    m[1][1] * m[2][0] * m[2][0] - m[2][2] * m[1][0] * m[1][0];
  const double c1 = m[0][0] * m[1][1] - m[1][0] * m[1][0] + m[0][0] * m[2][2] - m[2][0] * m[2][0] +
                    m[1][1] * m[2][2] - m[2][1] * m[2][1];
  const double c2 = m[0][0] + m[1][1] + m[2][2];
  const double inv3 = 1.0 / 3.0;
  const double c2_3 = c2 * inv3;
  // (a >= 1/6 or so: the largest magnitude is in [1, 2) and the trace all but zero)
  const double a = std::max((c2 * c2_3 - c1) * inv3, 0.0);
  const double b = 0.5 * (c0 + c2_3 * (2.0 * c2_3 * c2_3 - c1));
  const double rho = std::sqrt(a), arho = a * rho;
  const double c = b / arho, ac = std::abs(c);
  const double t = detail::cubicRoot(ac < 1.0 ? ac : 1.0);  // (rounding puts |c| a little above 1 at a double root)
  // The other two roots from the quadratic left, y = rho (-t/2 +- h): since 4 - t^2 = 4 (1 - c^2) /
  // (t^2 - 1)^2, h = sqrt(3 q) / (a rho (t^2 - 1)) with q = a^3 - b^2, as computeRoots forms it (in
  // 4 - t^2, t's own rounding would weigh four times as much where the pair's gap is small).
  const double q = std::max(a * a * a - b * b, 0.0);
  const double half = 0.5 * t, h = std::sqrt(3.0 * q) / (arho * (t * t - 1.0));
  CubicRoots r{0, 0, 0, c2_3, rho, half, h, c >= 0};
  if (r.top)
  {
    r.l2 = c2_3 + rho * t;
    r.l1 = c2_3 + rho * (h - half);
    r.l0 = c2_3 - rho * (half + h);
  }
  else
  {
    r.l0 = c2_3 - rho * t;
    r.l1 = c2_3 + rho * (half - h);
    r.l2 = c2_3 + rho * (half + h);
  }
  return r;
}
}  // namespace

void covarianceAxis(const Eigen::Matrix3d& cov, int which, Eigen::Vector3d& eigenvalues, Eigen::Vector3d& axis)
{
  axis.setZero();
  double m[3][3], shift, up;
  if (!scaledShifted(cov, m, shift, up))
  {
    eigenvalues.setConstant(shift);  // a multiple of the identity: computeDirect's identity columns
    axis(which) = 1.0;
    return;
  }
  const CubicRoots r = cubicRoots(m);
  double l0 = r.l0, l1 = r.l1, l2 = r.l2;
  const double c2_3 = r.c2_3, rho = r.rho, half = r.half, h = r.h;
  const bool top = r.top;
  const int k = top ? 2 : 0;
  if (l2 - l0 <= kEps)
  {
    eigenvalues = Eigen::Vector3d(l0 * up + shift, l1 * up + shift, l2 * up + shift);
    axis(which) = 1.0;  // three equal eigenvalues: computeDirect's identity
    return;
  }
  // m shifted by the eigenvalue apart, its kernel vk and representative column rep: found once,
  // where first needed (a close pair, or the vector asked for is that eigenvalue's or in the pair)
  double mk[3][3];
  Eigen::Vector3d vk;
  int rep = -1;
  const double lk = top ? l2 : l0;
  const auto kernelApart = [&] {
    if (rep >= 0) return;
    shifted(m, lk, mk);
    rep = extractKernel(mk, vk);
  };
  const auto representative = [&] { return Eigen::Vector3d(mk[rep][0], mk[rep][1], mk[rep][2]).normalized(); };
  const bool close_pair = h > 0 && h < kClosePair;
  if (close_pair)
  {
    // The gap from q, a small difference of two cubes, is good to only ~sqrt(eps) here (as in
    // computeDirect). Again from Q = m - mu I - (lk - mu) vk vk^T about the pair's mean mu: Q vk = 0
    // and its other eigenvalues are +- g / 2, so its squared Frobenius norm g^2 / 2 is a sum without
    // cancellation, the gap to about eps.
    kernelApart();
    const double mu = top ? c2_3 - rho * half : c2_3 + rho * half, sk = lk - mu;
    const double q00 = m[0][0] - mu - sk * vk(0) * vk(0), q11 = m[1][1] - mu - sk * vk(1) * vk(1);
    const double q22 = m[2][2] - mu - sk * vk(2) * vk(2), q01 = m[0][1] - sk * vk(0) * vk(1);
    const double q02 = m[0][2] - sk * vk(0) * vk(2), q12 = m[1][2] - sk * vk(1) * vk(2);
    const double f2 = q00 * q00 + q11 * q11 + q22 * q22 + 2.0 * (q01 * q01 + q02 * q02 + q12 * q12);
    const double g_2 = 0.5 * std::sqrt(2.0 * f2);
    const double lo = mu - g_2, hi = mu + g_2;
    if (top)
      l0 = lo, l1 = hi;
    else
      l1 = lo, l2 = hi;
  }
  eigenvalues = Eigen::Vector3d(l0 * up + shift, l1 * up + shift, l2 * up + shift);
  // The kernel of m shifted by the asked-for eigenvalue, as computeDirect finds it; where two are
  // numerically equal (pair gap <= 2 eps times the other gap) the kernel is a plane, and computeDirect
  // takes the representative column of the other eigenvalue's kernel, orthogonal to its vector.
  if (which == k)
  {
    kernelApart();
    axis = vk;
    return;
  }
  const double pair_gap = top ? l1 - l0 : l2 - l1, apart_gap = top ? l2 - l1 : l1 - l0;
  if (pair_gap <= 2 * kEps * apart_gap)
  {
    kernelApart();
    axis = representative();
    return;
  }
  double mw[3][3];
  shifted(m, which == 0 ? l0 : l2, mw);
  extractKernel(mw, axis);
  if (!close_pair) return;
  // In a close pair that kernel may lean along the vector apart by its error: made orthogonal to it
  // (Gram-Schmidt) it lies in the pair's plane; if little is left, the representative column.
  const Eigen::Vector3d in_plane = axis - axis.dot(vk) * vk;
  if (in_plane.squaredNorm() >= 0.25)
    axis = in_plane.normalized();
  else
    axis = representative();
}

}  // namespace ring_curvature
