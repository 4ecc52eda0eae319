// covarianceAxis against Eigen's SelfAdjointEigenSolver::computeDirect, bit for bit: the
// eigenvalues and the asked-for eigenvector (smallest and largest) of covariances of every kind
// the primitives give (planes, lines, blobs, single points, far from the origin or near it),
// and of the matrices that take computeDirect's special branches: three equal eigenvalues, two
// nearly equal ones at either end (its orthogonalised vector), exact zeros, rank one and two.
#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <random>
#include <vector>

#include "../../src/core/covariance_axis.hpp"

using ring_curvature::covarianceAxis;

namespace
{
bool sameBits(const Eigen::Vector3d& a, const Eigen::Vector3d& b) { return std::memcmp(a.data(), b.data(), 24) == 0; }

// Expects covarianceAxis to give computeDirect's bits for m, both columns; counts which
// branch of computeDirect m takes in `branches` (0: all equal, 1: orthogonalised, 2: two kernels).
void expectSame(const Eigen::Matrix3d& m, int* branches = nullptr)
{
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> es;
  es.computeDirect(m);
  for (const int which : {0, 2})
  {
    Eigen::Vector3d ev, axis;
    covarianceAxis(m, which, ev, axis);
    ASSERT_TRUE(sameBits(ev, es.eigenvalues())) << "which " << which << "\n" << m << "\n"
                                                << ev.transpose() << "\n" << es.eigenvalues().transpose();
    ASSERT_TRUE(sameBits(axis, es.eigenvectors().col(which)))
        << "which " << which << "\n" << m << "\n" << axis.transpose() << "\n"
        << es.eigenvectors().col(which).transpose();
  }
  if (branches == nullptr) return;
  // (the branch, from the scaled eigenvalues as computeDirect sees them)
  const Eigen::Vector3d ev = es.eigenvalues();
  const double scale = (m - Eigen::Matrix3d::Identity() * (m.trace() / 3)).cwiseAbs().maxCoeff();
  const Eigen::Vector3d s = scale > 0 ? Eigen::Vector3d(ev / scale) : ev;
  const double eps = Eigen::NumTraits<double>::epsilon();
  const double d0 = s(2) - s(1), d1 = s(1) - s(0);
  if (s(2) - s(0) <= eps)
    ++branches[0];
  else if (d0 > d1 ? d1 <= 2 * eps * d1 : d0 <= 2 * eps * d1)  // (as computeDirect compares them)
    ++branches[1];
  else
    ++branches[2];
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
}  // namespace

TEST(CovarianceAxis, PrimitiveShapes)
{
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> far(-80, 80);
  int branches[3] = {0, 0, 0};
  for (int t = 0; t < 4000; ++t)
  {
    const Eigen::Vector3d c(far(rng), far(rng), far(rng) * 0.05);
    const int n = 1 + static_cast<int>(rng() % 200);
    Eigen::Vector3d sd;
    switch (t % 4)
    {
      case 0: sd = {1.0, 0.7, 0.003}; break;   // a plane with range noise
      case 1: sd = {0.9, 0.004, 0.002}; break;  // an edge chain
      case 2: sd = {0.05, 0.04, 0.03}; break;   // a corner cluster
      default: sd = {1.0, 1.0, 1.0}; break;     // nearly isotropic
    }
    expectSame(covarianceOf(rng, n, sd, c), branches);
  }
  EXPECT_GT(branches[2], 3000);  // most take the two kernels...
  EXPECT_GT(branches[0], 0);     // ... single points (zero matrix) the identity
}

TEST(CovarianceAxis, SpecialBranches)
{
  int branches[3] = {0, 0, 0};
  expectSame(Eigen::Matrix3d::Zero(), branches);
  expectSame(Eigen::Matrix3d::Identity() * 2.5, branches);
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(-1, 1);
  for (int t = 0; t < 3000; ++t)
  {
    const Eigen::Matrix3d R = randomRotation(rng);
    const double a = std::ldexp(1.0 + u(rng), static_cast<int>(rng() % 40) - 20);
    // two eigenvalues equal but for a few ulps, at the low end (a line) or the high end (a disc),
    // an exact rank one or two, or an exactly repeated pair
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
    const Eigen::Matrix3d m = R * d.asDiagonal() * R.transpose();
    expectSame(0.5 * (m + m.transpose()), branches);
  }
  // each of computeDirect's three branches met, the orthogonalisation many times
  std::printf("branches: equal %d, orthogonalised %d, two kernels %d\n", branches[0], branches[1], branches[2]);
  EXPECT_GT(branches[0], 0);
  EXPECT_GT(branches[1], 100);
  EXPECT_GT(branches[2], 100);
}
