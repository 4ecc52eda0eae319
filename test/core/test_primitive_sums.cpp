// The primitives' box, centroid and moment sums (primitiveSums) against their definition, bit for
// bit: the box from std::min / std::max of the grid points' floats (as it was before the sums
// became one pass), and about the first point r the double sums over the grid points, in index
// order, of w d, (w d) d and (w d) rot(d), d = p - r, w = 1 + the duplicates of the point (so
// w = 1, the plain terms, in a primitive without duplicates), from which the centroid is
// r + sum(w d) / n and the moments sum(w d d^T) - sum(w d) sum(w d)^T / n, n the points with the
// duplicates. Primitives of many sizes (one point up to a few hundred, not multiples of any
// vector width) with no duplicates (the unweighted loop), a few (most weights 1) and many,
// weights up to 2^32, coordinates far from the origin so that every rounding shows in the last
// bits, and signed zeros and tiny coordinates for the box (the accuracy against a long double
// reference: test_primitive_sums_accuracy.cpp).
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <numeric>
#include <random>
#include <vector>

#include "primitives/primitive_sums.hpp"

using namespace ring_curvature;

namespace
{
using Grid = std::vector<double>;

// The definition, one grid point and one coordinate at a time: grid point k (sp[k], k < ng)
// stands for 1 + dups[k] points; n = np
void reference(const std::uint32_t* sp, std::uint32_t ng, std::uint32_t np, const std::vector<std::uint64_t>& dups,
               const Grid& gx, const Grid& gy, const Grid& gz, PrimitiveSums& out)
{
  const Grid* g[3] = {&gx, &gy, &gz};
  float lo[3], hi[3];
  double r[3], s[3] = {0, 0, 0};
  double xx = 0, yy = 0, zz = 0, xy = 0, yz = 0, zx = 0;
  for (int i = 0; i < 3; ++i)
  {
    r[i] = (*g[i])[sp[0]];
    lo[i] = hi[i] = static_cast<float>(r[i]);  // the first point starts the box
  }
  for (std::uint32_t k = 0; k < ng; ++k)
  {
    const double w = 1.0 + static_cast<double>(dups[k]);
    double d[3], wd[3];
    for (int i = 0; i < 3; ++i)
    {
      const double p = (*g[i])[sp[k]];
      lo[i] = std::min(lo[i], static_cast<float>(p));
      hi[i] = std::max(hi[i], static_cast<float>(p));
      d[i] = p - r[i];
      wd[i] = w * d[i];
      s[i] = s[i] + wd[i];
    }
    xx = xx + wd[0] * d[0];
    yy = yy + wd[1] * d[1];
    zz = zz + wd[2] * d[2];
    xy = xy + wd[0] * d[1];
    yz = yz + wd[1] * d[2];
    zx = zx + wd[2] * d[0];
  }
  const double n = static_cast<double>(np);
  const double mean[3] = {s[0] / n, s[1] / n, s[2] / n};
  std::memset(&out, 0, sizeof out);
  for (int i = 0; i < 3; ++i)
  {
    out.lo[i] = lo[i];
    out.hi[i] = hi[i];
    out.centroid[i] = static_cast<float>(r[i] + mean[i]);
  }
  out.m[0] = xx - s[0] * mean[0];
  out.m[1] = yy - s[1] * mean[1];
  out.m[2] = zx - s[2] * mean[0];
  out.m[3] = zz - s[2] * mean[2];
  out.mxy[0] = xy - s[0] * mean[1];
  out.mxy[1] = yz - s[1] * mean[2];
}

// Each grid point's duplicates, counted by scanning the duplicates' positions sp[ng, np)
std::vector<std::uint64_t> duplicatesOf(const std::vector<std::uint32_t>& sp, std::uint32_t ng)
{
  std::vector<std::uint64_t> dups(ng, 0);
  for (std::size_t j = ng; j < sp.size(); ++j)
    for (std::uint32_t k = 0; k < ng; ++k) dups[k] += sp[j] == sp[k] ? 1 : 0;
  return dups;
}

using SumsFn = void (*)(const std::uint32_t*, std::uint32_t, std::uint32_t, const std::uint32_t*, const double*,
                        const double*, const double*, PrimitiveSums&);

// The forms under test (one: the clone the loader picked for this CPU)
std::vector<SumsFn> forms() { return {primitiveSums}; }

bool sameSums(const PrimitiveSums& got, const PrimitiveSums& want)
{
  // lane 3 (a copy of z) is not part of the result
  return std::memcmp(got.lo, want.lo, 3 * sizeof(float)) == 0 && std::memcmp(got.hi, want.hi, 3 * sizeof(float)) == 0 &&
         std::memcmp(got.centroid, want.centroid, 3 * sizeof(float)) == 0 &&
         std::memcmp(got.m, want.m, sizeof want.m) == 0 && std::memcmp(got.mxy, want.mxy, sizeof want.mxy) == 0;
}

// Each form this CPU runs against the reference on one primitive (sp: its ng grid points, then
// its duplicates; count: the duplicates per grid position, as the forms read them; dups: as the
// reference reads them)
void expectFormsMatch(const std::vector<std::uint32_t>& sp, std::uint32_t ng, std::uint32_t np,
                      const std::vector<std::uint64_t>& dups, const std::vector<std::uint32_t>& count, const Grid& gx,
                      const Grid& gy, const Grid& gz)
{
  PrimitiveSums want;
  reference(sp.data(), ng, np, dups, gx, gy, gz, want);
  int form = 0;
  for (const SumsFn f : forms())
  {
    PrimitiveSums got;
    std::memset(&got, 0, sizeof got);
    f(sp.data(), ng, np, count.data(), gx.data(), gy.data(), gz.data(), got);
    EXPECT_TRUE(sameSums(got, want)) << "form " << form << " ng " << ng << " np " << np;
    ++form;
  }
}

// Random primitives of grid g: ng distinct grid points, then duplicates (each a twin of one of
// them, some of several); the counts per grid position as extract makes them, every other
// position holding garbage (other primitives' counts, never read). Each form against the
// reference.
int checkBitForBit(const Grid& gx, const Grid& gy, const Grid& gz, std::mt19937& rng)
{
  const auto n_grid = static_cast<std::uint32_t>(gx.size());
  std::vector<std::uint32_t> all(n_grid), count(n_grid);
  std::iota(all.begin(), all.end(), 0u);
  std::uniform_int_distribution<std::uint32_t> garbage(0, 1000);
  int checked = 0, few = 0, many = 0;
  for (std::uint32_t ng = 1; ng < 400; ng += (ng < 40 ? 1 : 37))
    for (const std::uint32_t ndup : {0u, 1u, 3u, ng / 4, (ng + 3) / 4, ng / 2 + 1, 2 * ng})
    {
      std::shuffle(all.begin(), all.end(), rng);
      std::vector<std::uint32_t> sp(all.begin(), all.begin() + ng);
      std::uniform_int_distribution<std::uint32_t> earlier(0, ng - 1);
      for (std::uint32_t k = 0; k < ndup; ++k) sp.push_back(sp[earlier(rng)]);  // a twin of a grid point
      const auto np = static_cast<std::uint32_t>(sp.size());
      for (std::uint32_t& c : count) c = garbage(rng);
      for (std::uint32_t k = 0; k < ng; ++k) count[sp[k]] = 0;
      for (std::uint32_t k = ng; k < np; ++k) ++count[sp[k]];
      expectFormsMatch(sp, ng, np, duplicatesOf(sp, ng), count, gx, gy, gz);
      ++checked;
      few += ndup > 0 && ndup * 4 < ng;
      many += ndup > 0 && ndup * 4 >= ng;
    }
  EXPECT_GT(few, 30);
  EXPECT_GT(many, 30);
  return checked;
}

TEST(PrimitiveSums, BitForBitAgainstPerPointSums)
{
  std::mt19937 rng(7);
  const std::uint32_t n_grid = 5000;
  Grid gx(n_grid), gy(n_grid), gz(n_grid);
  std::uniform_real_distribution<double> off(-80.0, 80.0), spread(-3.0, 3.0);
  for (std::uint32_t p = 0; p < n_grid; ++p)
  {
    // clusters around far centres, so that the differences' and sums' roundings matter
    const double cx = off(rng) * (p % 7 == 0 ? 1.0 : 0.01);
    gx[p] = 40.0 + cx + spread(rng);
    gy[p] = -25.0 + spread(rng) * 0.3;
    gz[p] = -1.7 + spread(rng) * 0.05;
  }
  EXPECT_GT(checkBitForBit(gx, gy, gz, rng), 200);
}

// Weights far beyond a few: counts up to 2^32 - 100 (np still a uint32), which the AVX2 form
// converts to double by the bits of 2^52 + c; and a primitive with few duplicates, all of one
// grid point
TEST(PrimitiveSums, LargeWeights)
{
  std::mt19937 rng(5);
  const std::uint32_t n_grid = 200;
  Grid gx(n_grid), gy(n_grid), gz(n_grid);
  std::uniform_real_distribution<double> spread(-2.0, 2.0);
  for (std::uint32_t p = 0; p < n_grid; ++p)
  {
    gx[p] = 30.0 + spread(rng);
    gy[p] = 60.0 + spread(rng);
    gz[p] = -1.0 + spread(rng) * 0.1;
  }
  const std::vector<std::vector<std::uint32_t>> cases = {
      {0, 4294967196u, 3, 0, 50, 20},
      {0, 2147483648u, 1u << 20, (1u << 20) + 1, 16777217u, 9007199u},
      {7, 0, 1, 2, 3, 4, 5, 6, 8, 9, 10, 11, 12, 13, 255, 256, 65535, 65536}};
  for (const auto& counts : cases)
  {
    const auto ng = static_cast<std::uint32_t>(counts.size());
    std::vector<std::uint32_t> sp(ng), count(n_grid, 0);
    std::vector<std::uint64_t> dups(ng);
    std::uint64_t np = ng;
    for (std::uint32_t k = 0; k < ng; ++k)
    {
      sp[k] = 3 * k + 1;
      count[sp[k]] = counts[k];
      dups[k] = counts[k];
      np += counts[k];
    }
    ASSERT_LT(np, std::uint64_t{1} << 32);
    expectFormsMatch(sp, ng, static_cast<std::uint32_t>(np), dups, count, gx, gy, gz);
  }
  // few: 24 duplicates of one of 100 grid points (24 * 4 < 100)
  std::vector<std::uint32_t> sp(100), count(n_grid, 0);
  std::vector<std::uint64_t> dups(100, 0);
  for (std::uint32_t k = 0; k < 100; ++k) sp[k] = 2 * k;
  count[sp[57]] = 24;
  dups[57] = 24;
  expectFormsMatch(sp, 100, 124, dups, count, gx, gy, gz);
}

// The box, now min / max of doubles converted once, against min / max of the floats where ties
// and rounding decide: +0 and -0 (equal, the earlier one stays, sign and all), doubles that round
// to the same float, and tiny and large magnitudes of either sign
TEST(PrimitiveSums, BoxOfDoublesIsTheBoxOfFloats)
{
  std::mt19937 rng(11);
  // all of them; then those a zero's sign decides the min of, then the max of
  const std::vector<std::vector<double>> pools = {
      {0.0, -0.0, 1e-30, -1e-30, 1e-40, -1e-40, 0.5, -0.5, 1.0, 1.0 + 1e-12, 1.0 - 1e-12, 80.0, 80.0 + 1e-7,
       80.0 - 1e-7, -80.0, -80.0 + 1e-9, 3.4e38, -3.4e38},
      {0.0, -0.0, 0.0, -0.0, 1e-30, 80.0},
      {0.0, -0.0, 0.0, -0.0, -1e-30, -80.0}};
  const std::uint32_t n_grid = 3000;
  for (const auto& values : pools)
  {
    std::uniform_int_distribution<std::size_t> pick(0, values.size() - 1);
    Grid gx(n_grid), gy(n_grid), gz(n_grid);
    for (std::uint32_t p = 0; p < n_grid; ++p)
    {
      gx[p] = values[pick(rng)];
      gy[p] = values[pick(rng)];
      gz[p] = values[pick(rng)];
    }
    std::uniform_int_distribution<std::uint32_t> pos(0, n_grid - 1);
    for (std::uint32_t ng = 1; ng < 60; ++ng)
      for (int rep = 0; rep < 20; ++rep)
      {
        std::vector<std::uint32_t> sp;
        for (std::uint32_t k = 0; k < ng; ++k) sp.push_back(pos(rng));
        PrimitiveSums want;
        reference(sp.data(), ng, ng, std::vector<std::uint64_t>(ng, 0), gx, gy, gz, want);
        for (const SumsFn f : forms())
        {
          PrimitiveSums got;
          f(sp.data(), ng, ng, nullptr, gx.data(), gy.data(), gz.data(), got);  // no duplicates: no counts read
          EXPECT_EQ(0, std::memcmp(got.lo, want.lo, 3 * sizeof(float))) << "ng " << ng;
          EXPECT_EQ(0, std::memcmp(got.hi, want.hi, 3 * sizeof(float))) << "ng " << ng;
        }
      }
  }
}
}  // namespace
