// covarianceAxis against a long-double reference (Eigen's iterative SelfAdjointEigenSolver on
// the same matrix, 11 more bits), side by side with Eigen's SelfAdjointEigenSolver::computeDirect,
// whose closed form it replaces: on each class of covariances (planes, edge chains, corner blobs
// and isotropic ones from points, as the primitives give them; diagonal ones turned by random
// rotations and scaled by 1e-8 to 1e4 m^2: planar, linear, isotropic, nearly equal pairs at
// either end, a sweep of the cubic's whole range; the special matrices: zero, multiples of the
// identity, exact rank one and two, exactly repeated pairs), its eigenvalue errors (relative to
// the largest magnitude) and its vector's angle error (to the reference's eigenspace of the
// eigenvalue asked for) may not exceed computeDirect's by more than a small factor, neither at
// their largest (the vectors' taken relative to their eigenvalue's gap, see Errors) nor on
// average. Prints the statistics.
#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>
#include <limits>
#include <random>
#include <vector>

#include "primitives/covariance_axis.hpp"

using ring_curvature::covarianceAxis;

namespace
{
using Matrix3l = Eigen::Matrix<long double, 3, 3>;
using Vector3l = Eigen::Matrix<long double, 3, 1>;
constexpr double kEps = 2.220446049250313e-16;

// Largest and summed errors of one solver on one class, for one column; and the largest vector
// error times its eigenvalue's gap over the largest |eigenvalue| (`conditioned`). An eigenvector
// moves by up to |E| / gap for a perturbation E of the matrix (Davis-Kahan), so where the gap is
// small even rounding the matrix to double (E ~ eps top) moves it by eps top / gap: the largest
// raw errors of a class are then those of its closest pairs, at the rounding's level for both
// solvers, and which of the two is larger is chance (a blob's nearly equal pair gave 2.1e-13
// against computeDirect's 5.1e-14 on another compiler's matrices). Times gap / top, each error is
// in units of what the matrix allows, and the largest is a fair comparison.
struct Errors
{
  double value_max = 0, value_sum = 0, vector_max = 0, vector_sum = 0, conditioned_max = 0;
  int n = 0;
  void add(double value, double vector, double gap_over_top)
  {
    value_max = std::max(value_max, value), value_sum += value;
    vector_max = std::max(vector_max, vector), vector_sum += vector;
    conditioned_max = std::max(conditioned_max, vector * gap_over_top);
    ++n;
  }
};

// The errors of (ev, v) for column `which` of m against the reference (L, V): the largest
// eigenvalue error over the largest |eigenvalue|, and the sine of the angle between v and the
// span of the reference vectors whose eigenvalues are within 4 eps (relative) of the asked-for
// one (its eigenspace, as far as double input defines it: with a pair that close any vector of
// the plane is right).
void errorsOf(const Vector3l& L, const Matrix3l& V, int which, const Eigen::Vector3d& ev, const Eigen::Vector3d& v,
              double& value, double& vector)
{
  const long double top = std::max(std::abs(L(0)), std::abs(L(2)));
  long double ve = 0;
  for (int i = 0; i < 3; ++i) ve = std::max(ve, std::abs(static_cast<long double>(ev(i)) - L(i)));
  value = top > 0 ? static_cast<double>(ve / top) : static_cast<double>(ve);
  // (the norm of v's part outside that span, over |v|: a sine accurate where it is small)
  const Vector3l vl = v.cast<long double>();
  Vector3l out = vl;
  for (int j = 0; j < 3; ++j)
    if (std::abs(L(j) - L(which)) <= 4 * kEps * top) out -= vl.dot(V.col(j)) * V.col(j);
  vector = static_cast<double>(out.norm() / vl.norm());
}

struct Class
{
  const char* name = "";
  Errors ours[2], direct[2];  // which 0, which 2
  int sign_flips = 0, sign_checked = 0;
};

// Both solvers on m, against the reference.
void measure(const Eigen::Matrix3d& m, Class& cls)
{
  Eigen::SelfAdjointEigenSolver<Matrix3l> ref(m.cast<long double>());
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> cd;
  cd.computeDirect(m);
  const Vector3l& L = ref.eigenvalues();
  const long double top = std::max(std::abs(L(0)), std::abs(L(2)));
  for (int w = 0; w < 2; ++w)
  {
    const int which = 2 * w;
    Eigen::Vector3d ev, axis;
    covarianceAxis(m, which, ev, axis);
    ASSERT_TRUE(ev(0) <= ev(1) && ev(1) <= ev(2)) << m << "\n" << ev.transpose();
    ASSERT_NEAR(axis.norm(), 1.0, 4 * kEps) << m;
    // the gap: to the nearest eigenvalue outside the eigenspace errorsOf measures against
    long double apart = 0;
    for (int j = 0; j < 3; ++j)
    {
      const long double d = std::abs(L(j) - L(which));
      if (d > 4 * kEps * top && (apart == 0 || d < apart)) apart = d;
    }
    const double gap_over_top = top > 0 ? static_cast<double>(apart / top) : 0.0;
    double value, vector;
    errorsOf(L, ref.eigenvectors(), which, ev, axis, value, vector);
    cls.ours[w].add(value, vector, gap_over_top);
    errorsOf(L, ref.eigenvectors(), which, cd.eigenvalues(), cd.eigenvectors().col(which), value, vector);
    cls.direct[w].add(value, vector, gap_over_top);
    // computeDirect's sign, where the eigenvalue is clearly apart (its kernel choice no near tie)
    const long double gap = std::min(which == 0 ? L(1) - L(0) : L(2) - L(1), L(2) - L(0));
    if (gap > 1e-3L * top && vector < 1e-6)
    {
      ++cls.sign_checked;
      if (axis.dot(cd.eigenvectors().col(which)) < 0) ++cls.sign_flips;
    }
  }
}

// Prints the class's statistics and expects ours within `factor` of computeDirect's (plus a few
// eps, where computeDirect's are zero), at the largest and on average: the vectors' largest
// errors times their eigenvalue's gap (see Errors).
void expectNoWorse(const Class& cls, double factor = 2.0)
{
  // (the vectors' largest errors times gap / top: a backward error of 16 eps top, which forming
  // the cubic's coefficients from the matrix alone comes close to, is the rounding's level)
  const double floor = 4 * kEps, conditioned_floor = 16 * kEps;
  for (int w = 0; w < 2; ++w)
  {
    const Errors& o = cls.ours[w];
    const Errors& d = cls.direct[w];
    std::printf("%-14s which %d (%4d): values max %.2e / %.2e mean %.2e / %.2e; vector max %.2e / %.2e "
                "mean %.2e / %.2e, times gap / top max %.2e / %.2e (ours / computeDirect)\n",
                cls.name, 2 * w, o.n, o.value_max, d.value_max, o.value_sum / o.n, d.value_sum / d.n, o.vector_max,
                d.vector_max, o.vector_sum / o.n, d.vector_sum / d.n, o.conditioned_max, d.conditioned_max);
    EXPECT_LE(o.value_max, factor * d.value_max + floor) << cls.name << " which " << 2 * w;
    EXPECT_LE(o.value_sum, factor * d.value_sum + floor * o.n) << cls.name << " which " << 2 * w;
    EXPECT_LE(o.conditioned_max, factor * d.conditioned_max + conditioned_floor) << cls.name << " which " << 2 * w;
    EXPECT_LE(o.vector_sum, factor * d.vector_sum + floor * o.n) << cls.name << " which " << 2 * w;
  }
  std::printf("%-14s sign as computeDirect's: %d of %d clearly apart\n", cls.name,
              cls.sign_checked - cls.sign_flips, cls.sign_checked);
  EXPECT_LE(cls.sign_flips * 1000, cls.sign_checked) << cls.name;  // (near ties of its kernel choice only)
}

// A uniformly random rotation (a normalised 4-D normal sample as a quaternion).
Eigen::Matrix3d randomRotation(std::mt19937& rng)
{
  std::normal_distribution<double> g;
  const double w = g(rng), x = g(rng), y = g(rng), z = g(rng);
  return Eigen::Quaterniond(w, x, y, z).normalized().toRotationMatrix();
}

// The covariance of n points x = c + R diag(sd) u, u standard normal (as extract forms it:
// moments about the mean, divided by n).
Eigen::Matrix3d covarianceOf(std::mt19937& rng, int n, const Eigen::Vector3d& sd, const Eigen::Vector3d& c)
{
  std::normal_distribution<double> g;
  const Eigen::Matrix3d R = randomRotation(rng);
  std::vector<Eigen::Vector3d> p(static_cast<std::size_t>(n));
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();
  for (auto& v : p)
  {
    v = c + R * Eigen::Vector3d(sd(0) * g(rng), sd(1) * g(rng), sd(2) * g(rng));
    mean += v;
  }
  mean /= n;
  Eigen::Matrix3d cov = Eigen::Matrix3d::Zero();
  for (const auto& v : p) cov += (v - mean) * (v - mean).transpose();
  return cov / n;
}

// R diag(d) R^T, symmetrised, scaled by 10^[-8, 4].
Eigen::Matrix3d turned(std::mt19937& rng, const Eigen::Vector3d& d)
{
  std::uniform_real_distribution<double> u(-8, 4);
  const Eigen::Matrix3d R = randomRotation(rng);
  const Eigen::Matrix3d m = R * (d * std::pow(10.0, u(rng))).asDiagonal() * R.transpose();
  return 0.5 * (m + m.transpose());
}

// `count` matrices from make(rng, t) into one class, then its checks.
void runClass(const char* name, int count, const std::function<Eigen::Matrix3d(std::mt19937&, int)>& make)
{
  Class cls;
  cls.name = name;
  std::mt19937 rng(7);
  for (int t = 0; t < count; ++t)
  {
    measure(make(rng, t), cls);
    if (::testing::Test::HasFatalFailure()) return;
  }
  expectNoWorse(cls);
}

double logUniform(std::mt19937& rng, double lo, double hi)
{
  return std::pow(10.0, std::uniform_real_distribution<double>(lo, hi)(rng));
}
}  // namespace

// The Newton step's seed is what its comment says: the degree-8 Chebyshev interpolant of the
// cubic's largest root on [0, 1], computed again here in long double from its definition (the
// nodes, the Chebyshev coefficients, the expansion into powers of c), and no constant edited
// since; its error and the error after the Newton step on a dense grid of c.
TEST(CovarianceAxis, CubicSeedIsTheChebyshevInterpolant)
{
  // (valgrind computes long double as double: then there are no spare bits to check with)
  volatile long double tiny = std::numeric_limits<long double>::epsilon();
  if (1.0L + tiny == 1.0L) GTEST_SKIP() << "long double arithmetic has no more precision than double here";
  constexpr int N = 9;  // degree 8
  const long double pi = std::acos(-1.0L);
  const auto root = [](long double c) { return 2 * std::cos(std::acos(c) / 3); };
  long double cheb[N] = {};  // in x = 2 c - 1 on [-1, 1]
  for (int j = 0; j < N; ++j)
  {
    const long double th = pi * (j + 0.5L) / N, f = root((std::cos(th) + 1) / 2);
    for (int k = 0; k < N; ++k) cheb[k] += 2.0L / N * f * std::cos(k * th);
  }
  cheb[0] /= 2;
  // T_k in powers of x (T_k = 2 x T_k-1 - T_k-2), then x = 2 c - 1 by the binomial theorem
  long double T[N][N] = {}, in_x[N] = {}, in_c[N] = {};
  T[0][0] = T[1][1] = 1;
  for (int k = 2; k < N; ++k)
    for (int i = 0; i < N; ++i) T[k][i] = (i > 0 ? 2 * T[k - 1][i - 1] : 0) - T[k - 2][i];
  for (int k = 0; k < N; ++k)
    for (int i = 0; i < N; ++i) in_x[i] += cheb[k] * T[k][i];
  for (int i = 0; i < N; ++i)
  {
    long double binomial = 1;  // C(i, j)
    for (int j = 0; j <= i; ++j)
    {
      in_c[j] += in_x[i] * binomial * std::ldexp(1.0L, j) * ((i - j) % 2 ? -1 : 1);
      binomial = binomial * (i - j) / (j + 1);
    }
  }
  // The expansion into powers of c cancels terms far larger than the coefficients: in x86's 80-bit
  // long double (where the constants were computed) that leaves errors up to ~1e-14, which a
  // 128-bit long double (AArch64) shows against the exact interpolant. The seed only starts a
  // Newton step (checked below), so 1e-14 is the claim: the constants are that interpolant.
  for (int i = 0; i < N; ++i)
    EXPECT_NEAR(ring_curvature::detail::kCubicSeed[i], static_cast<double>(in_c[i]), 1e-14) << "coefficient " << i;
  double seed_error = 0, root_error = 0;
  for (int s = 0; s <= 200000; ++s)
  {
    const double c = s / 200000.0;
    double seed = 0;
    for (int i = N - 1; i >= 0; --i) seed = seed * c + ring_curvature::detail::kCubicSeed[i];
    const long double t = root(c);
    seed_error = std::max(seed_error, static_cast<double>(std::fabs(seed - t)));
    root_error = std::max(root_error, static_cast<double>(std::fabs(ring_curvature::detail::cubicRoot(c) - t)));
  }
  std::printf("cubic seed: error %.3g before the Newton step, %.3g after\n", seed_error, root_error);
  EXPECT_LE(seed_error, 3.7e-9);
  EXPECT_LE(root_error, 4.5e-16);  // (t in [sqrt 3, 2]: its ulp is 2.2e-16 or 4.4e-16)
}

TEST(CovarianceAxis, PrimitiveShapes)
{
  const Eigen::Vector3d sds[4] = {{1.0, 0.7, 0.003}, {0.9, 0.004, 0.002}, {0.05, 0.04, 0.03}, {1.0, 1.0, 1.0}};
  const char* names[4] = {"points plane", "points edge", "points corner", "points blob"};
  for (int s = 0; s < 4; ++s)
    runClass(names[s], 3000, [&](std::mt19937& rng, int) {
      std::uniform_real_distribution<double> far(-80, 80);
      const Eigen::Vector3d c(far(rng), far(rng), far(rng) * 0.05);
      return covarianceOf(rng, 2 + static_cast<int>(rng() % 200), sds[s], c);
    });
}

TEST(CovarianceAxis, TurnedDiagonals)
{
  std::uniform_real_distribution<double> u(0, 1);
  runClass("planar", 5000, [&](std::mt19937& rng, int) {
    return turned(rng, {logUniform(rng, -9, -2), 0.02 + u(rng), 1.0});
  });
  runClass("linear", 5000, [&](std::mt19937& rng, int) {
    return turned(rng, {logUniform(rng, -9, -2), logUniform(rng, -9, -2), 1.0});
  });
  runClass("isotropic", 5000, [&](std::mt19937& rng, int) {
    const double s = logUniform(rng, -12, -1);
    return turned(rng, {1.0 + s * u(rng), 1.0 + s * u(rng), 1.0 + s * u(rng)});
  });
  runClass("pair low", 5000, [&](std::mt19937& rng, int) {
    const double x = 0.001 + u(rng) * 0.5;
    return turned(rng, {x, x * (1 + logUniform(rng, -16, -1)), 1.0});
  });
  runClass("pair high", 5000, [&](std::mt19937& rng, int) {
    return turned(rng, {u(rng) * 0.5, 1.0, 1.0 + logUniform(rng, -16, -1)});
  });
  // the cubic's whole range, c = cos 3 theta from 1 to -1: eigenvalues 2.5 + 2 cos(theta + 2 pi k / 3)
  runClass("sweep", 5000, [&](std::mt19937& rng, int t) {
    const double theta = (t + 0.5) / 5000 * M_PI / 3, third = 2 * M_PI / 3;
    return turned(rng, {2.5 + 2 * std::cos(theta + 2 * third), 2.5 + 2 * std::cos(theta + third),
                        2.5 + 2 * std::cos(theta)});
  });
}

TEST(CovarianceAxis, SpecialMatrices)
{
  // zero and multiples of the identity: the identity column, the eigenvalues exact
  for (const double s : {0.0, 2.5, 1e-9, 3e5})
    for (const int which : {0, 2})
    {
      Eigen::Vector3d ev, axis;
      covarianceAxis(Eigen::Matrix3d::Identity() * s, which, ev, axis);
      EXPECT_EQ(ev, Eigen::Vector3d::Constant(s));
      EXPECT_EQ(axis, Eigen::Vector3d::Unit(which));
    }
  // diagonal ones of rank one and two, and with an exactly repeated pair: the matrix shifted by
  // the pair's eigenvalue is exactly of rank one, every cross product of its columns zero
  // (computeDirect's representative column, where the kernel would be 0 / 0)
  for (const double a : {1.0, 0.3, 7e-5})
    for (int i = 0; i < 3; ++i)
      for (const double other : {0.0, 0.25 * a})
      {
        Eigen::Vector3d d = Eigen::Vector3d::Constant(other);
        d(i) = a;
        for (const int which : {0, 2})
        {
          Eigen::Vector3d ev, axis;
          covarianceAxis(d.asDiagonal(), which, ev, axis);
          Eigen::Vector3d sorted = d;
          std::sort(sorted.data(), sorted.data() + 3);
          EXPECT_LE((ev - sorted).cwiseAbs().maxCoeff(), 4 * kEps * a) << d.transpose();
          EXPECT_NEAR(axis.norm(), 1.0, 4 * kEps) << d.transpose() << " which " << which;
          // the pair's vector orthogonal to e_i, the one apart along it
          const bool apart = (a > other) == (which == 2);
          EXPECT_NEAR(std::abs(axis(i)), apart ? 1.0 : 0.0, 4 * kEps) << d.transpose() << " which " << which;
        }
      }
  // two eigenvalues equal but for a few ulps, at the low end (a line) or the high end (a disc),
  // an exact rank one or two, or an exactly repeated pair
  std::uniform_real_distribution<double> u(-1, 1);
  runClass("special", 5000, [&](std::mt19937& rng, int t) {
    const double a = std::ldexp(1.0 + u(rng), static_cast<int>(rng() % 40) - 20);
    const double tiny = a * 1e-17 * static_cast<double>(rng() % 8);
    Eigen::Vector3d d;
    switch (t % 5)
    {
      case 0: d = {tiny, 0, a}; break;
      case 1: d = {0, a, a + tiny}; break;
      case 2: d = {0, 0, a}; break;
      case 3: d = {0, a * 0.3, a}; break;
      default: d = {a * 0.5, a * 0.5, a * (t % 2 ? 0.5 : 2.0)}; break;
    }
    const Eigen::Matrix3d R = randomRotation(rng);
    const Eigen::Matrix3d m = R * d.asDiagonal() * R.transpose();
    return Eigen::Matrix3d(0.5 * (m + m.transpose()));
  });
}
