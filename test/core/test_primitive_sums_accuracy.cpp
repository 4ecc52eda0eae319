// The primitives' centroid and moment sums (primitiveSums) against a long double two-pass
// reference over every point, duplicates included: the covariance and centroid are at least as
// close as those of the old scheme (a float centroid, the moments about it, per point), primitive
// by primitive and overall, for planes, lines and blobs of many sizes and extents about 80 m
// away (the sums bit for bit against their definition: test_primitive_sums.cpp).
#include <gtest/gtest.h>

#include <algorithm>
#include <cfloat>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <random>
#include <vector>

#include "primitives/primitive_sums.hpp"

using namespace ring_curvature;

namespace
{
using Grid = std::vector<double>;

// The scheme before the one pass, as a comparison: the centroid a float sum of the points'
// floats divided by n, the moments in double about that centroid
void oldScheme(const std::uint32_t* sp, std::uint32_t np, const Grid& gx, const Grid& gy, const Grid& gz,
               float centroid[3], double cov[3][3])
{
  const Grid* g[3] = {&gx, &gy, &gz};
  float sum[3] = {0, 0, 0};
  for (std::uint32_t k = 0; k < np; ++k)
    for (int i = 0; i < 3; ++i) sum[i] = sum[i] + static_cast<float>((*g[i])[sp[k]]);
  const float fn = static_cast<float>(np);
  for (int i = 0; i < 3; ++i) centroid[i] = sum[i] / fn;
  double m[3][3] = {};
  for (std::uint32_t k = 0; k < np; ++k)
  {
    double d[3];
    for (int i = 0; i < 3; ++i) d[i] = (*g[i])[sp[k]] - static_cast<double>(centroid[i]);
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) m[i][j] = m[i][j] + d[i] * d[j];
  }
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) cov[i][j] = m[i][j] / static_cast<double>(np);
}
// The long double two-pass covariance and mean of the points
void exact(const std::uint32_t* sp, std::uint32_t np, const Grid* g[3], long double mean[3], long double cov[3][3])
{
  for (int i = 0; i < 3; ++i)
  {
    long double s = 0;
    for (std::uint32_t k = 0; k < np; ++k) s += static_cast<long double>((*g[i])[sp[k]]);
    mean[i] = s / static_cast<long double>(np);
  }
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
    {
      long double s = 0;
      for (std::uint32_t k = 0; k < np; ++k)
      {
        const long double di = static_cast<long double>((*g[i])[sp[k]]) - mean[i],
                          dj = static_cast<long double>((*g[j])[sp[k]]) - mean[j];
        s += di * dj;
      }
      cov[i][j] = s / static_cast<long double>(np);
    }
}

// Each entry's error on the scale of its row and column, sqrt(C_ii C_jj): a plane's thin
// direction counts as much as its wide ones
long double covError(const double c[3][3], const long double e[3][3])
{
  long double worst = 0;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      worst = std::max(worst, std::fabs(static_cast<long double>(c[i][j]) - e[i][j]) / std::sqrt(e[i][i] * e[j][j]));
  return worst;
}

TEST(PrimitiveSums, AtLeastAsAccurateAsTheFloatCentroid)
{
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  const std::uint32_t sizes[] = {1, 2, 3, 5, 8, 13, 40, 150, 600, 2000, 5000};
  const double extents[] = {0.01, 0.03, 0.1, 0.3, 1.0, 3.0};
  long double sum_new = 0, sum_old = 0, sum_cnew = 0, sum_cold = 0;
  int cases = 0, better = 0;
  for (const std::uint32_t np : sizes)
    for (const double ext : extents)
      for (int shape = 0; shape < 3; ++shape)  // plane, line, blob
        for (const bool float_cloud : {false, true})
        {
          // about 80 m away, in a random direction, turned at random
          const double az = 2 * M_PI * unit(rng), centre[3] = {80 * std::cos(az), 80 * std::sin(az), 4 * unit(rng) - 2};
          const double a = 2 * M_PI * unit(rng), b = M_PI * unit(rng), ca = std::cos(a), sa = std::sin(a),
                       cb = std::cos(b), sb = std::sin(b);
          const double rot[3][3] = {{ca, -sa * cb, sa * sb}, {sa, ca * cb, -ca * sb}, {0, sb, cb}};
          const double half[3] = {ext / 2, shape == 2 ? ext / 2 : ext * (shape == 0 ? 0.3 + 0.7 * unit(rng) : 0.01) / 2,
                                  shape == 2 ? ext / 2 : ext * 0.005 + 0.0005};
          const std::uint32_t ng = np < 4 ? np : np - np / 4;  // a quarter duplicates
          Grid g3[3] = {Grid(ng), Grid(ng), Grid(ng)};
          for (std::uint32_t p = 0; p < ng; ++p)
          {
            double l[3];
            for (int i = 0; i < 3; ++i) l[i] = half[i] * (2 * unit(rng) - 1);
            for (int i = 0; i < 3; ++i)
            {
              const double v = centre[i] + rot[i][0] * l[0] + rot[i][1] * l[1] + rot[i][2] * l[2];
              g3[i][p] = float_cloud ? static_cast<double>(static_cast<float>(v)) : v;
            }
          }
          std::vector<std::uint32_t> sp;
          for (std::uint32_t k = 0; k < ng; ++k) sp.push_back(k);
          std::uniform_int_distribution<std::uint32_t> earlier(0, ng - 1);
          while (sp.size() < np) sp.push_back(earlier(rng));
          const Grid* g[3] = {&g3[0], &g3[1], &g3[2]};
          long double mean[3], ecov[3][3];
          exact(sp.data(), np, g, mean, ecov);
          std::vector<std::uint32_t> count(ng, 0);
          for (std::uint32_t k = ng; k < np; ++k) ++count[sp[k]];
          PrimitiveSums S;
          primitiveSums(sp.data(), ng, np, count.data(), g3[0].data(), g3[1].data(), g3[2].data(), S);
          const double n = static_cast<double>(np);
          const double cov[3][3] = {{S.m[0] / n, S.mxy[0] / n, S.m[2] / n},
                                    {S.mxy[0] / n, S.m[1] / n, S.mxy[1] / n},
                                    {S.m[2] / n, S.mxy[1] / n, S.m[3] / n}};
          float old_centroid[3];
          double old_cov[3][3];
          oldScheme(sp.data(), np, g3[0], g3[1], g3[2], old_centroid, old_cov);
          long double cnew = 0, cold = 0;  // the centroid's error [m]
          for (int i = 0; i < 3; ++i)
          {
            cnew = std::max(cnew, std::fabs(static_cast<long double>(S.centroid[i]) - mean[i]));
            cold = std::max(cold, std::fabs(static_cast<long double>(old_centroid[i]) - mean[i]));
          }
          // within 1e-12 m: where the mean is all but halfway between two floats, the exact
          // rounding and an error of the old one may pick either
          EXPECT_LE(cnew, cold + 1e-12L) << "np " << np << " extent " << ext << " shape " << shape;
          sum_cnew += cnew;
          sum_cold += cold;
          if (ng == 1)  // one distinct point: no spread, which the one pass gives exactly
          {
            for (int i = 0; i < 3; ++i)
              for (int j = 0; j < 3; ++j) EXPECT_EQ(0.0, cov[i][j]) << "np " << np;
            continue;
          }
          const long double enew = covError(cov, ecov), eold = covError(old_cov, ecov);
          // the slack: a few roundings of a double on each entry's scale
          EXPECT_LE(enew, eold + 16 * DBL_EPSILON) << "np " << np << " extent " << ext << " shape " << shape;
          sum_new += enew;
          sum_old += eold;
          better += enew < eold;
          ++cases;
        }
  std::printf("covariance error, summed over %d primitives: one pass %.3Lg, float centroid %.3Lg (%d better)\n",
              cases, sum_new, sum_old, better);
  std::printf("centroid error [m], summed: one pass %.3Lg, float centroid %.3Lg\n", sum_cnew, sum_cold);
  EXPECT_GT(cases, 300);
  EXPECT_LT(sum_new * 100, sum_old);  // clearly better overall, not just no worse
  EXPECT_LT(sum_cnew * 2, sum_cold);
  EXPECT_GT(better, cases * 9 / 10);
}
}  // namespace
