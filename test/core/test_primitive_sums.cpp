// The primitives' box, centroid and moment sums (primitiveSums: AVX2 intrinsics where the CPU has
// them, the plain vector code otherwise) against the per-point accumulation they replace, bit for
// bit: the box from std::min / std::max of float points, the centroid from their float sum in
// index order, and the six second moments summed in double, point by point, about the float
// centroid cast to double. Primitives of many sizes (one point up to a few hundred, not multiples
// of any vector width) with duplicates (later copies of earlier grid points, summed but not
// boxed), and coordinates far from the origin so that every rounding shows in the last bits.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <random>
#include <vector>

#include "../../src/core/primitive_sums.hpp"

using namespace ring_curvature;

namespace
{
void reference(const std::uint32_t* sp, std::uint32_t ng, std::uint32_t np, const std::vector<double>& gx,
               const std::vector<double>& gy, const std::vector<double>& gz, PrimitiveSums& out)
{
  float lo[3], hi[3], sum[3] = {0, 0, 0};
  // the first point starts the box
  for (int i = 0; i < 3; ++i) lo[i] = hi[i] = static_cast<float>((i == 0 ? gx : i == 1 ? gy : gz)[sp[0]]);
  for (std::uint32_t k = 0; k < np; ++k)
  {
    const float v[3] = {static_cast<float>(gx[sp[k]]), static_cast<float>(gy[sp[k]]), static_cast<float>(gz[sp[k]])};
    for (int i = 0; i < 3; ++i)
    {
      if (k < ng)
      {
        lo[i] = std::min(lo[i], v[i]);
        hi[i] = std::max(hi[i], v[i]);
      }
      sum[i] = sum[i] + v[i];
    }
  }
  const float fn = static_cast<float>(np);
  const float c[3] = {sum[0] / fn, sum[1] / fn, sum[2] / fn};
  double xx = 0, yy = 0, zz = 0, xy = 0, yz = 0, zx = 0;
  for (std::uint32_t k = 0; k < np; ++k)
  {
    const double dx = gx[sp[k]] - static_cast<double>(c[0]), dy = gy[sp[k]] - static_cast<double>(c[1]),
                 dz = gz[sp[k]] - static_cast<double>(c[2]);
    xx = xx + dx * dx;
    yy = yy + dy * dy;
    zz = zz + dz * dz;
    xy = xy + dx * dy;
    yz = yz + dy * dz;
    zx = zx + dz * dx;
  }
  std::memset(&out, 0, sizeof out);
  for (int i = 0; i < 3; ++i)
  {
    out.lo[i] = lo[i];
    out.hi[i] = hi[i];
    out.centroid[i] = c[i];
  }
  out.m[0] = xx;
  out.m[1] = yy;
  out.m[2] = zx;
  out.m[3] = zz;
  out.mxy[0] = xy;
  out.mxy[1] = yz;
}

TEST(PrimitiveSums, BitForBitAgainstPerPointSums)
{
  std::mt19937 rng(7);
  const std::uint32_t n_grid = 5000;
  std::vector<double> gx(n_grid), gy(n_grid), gz(n_grid);
  std::uniform_real_distribution<double> off(-80.0, 80.0), spread(-3.0, 3.0);
  for (std::uint32_t p = 0; p < n_grid; ++p)
  {
    // clusters around far centres, so the centroid's float rounding and the differences matter
    const double cx = off(rng) * (p % 7 == 0 ? 1.0 : 0.01);
    gx[p] = 40.0 + cx + spread(rng);
    gy[p] = -25.0 + spread(rng) * 0.3;
    gz[p] = -1.7 + spread(rng) * 0.05;
  }
  std::uniform_int_distribution<std::uint32_t> pos(0, n_grid - 1);
  int checked = 0;
  for (std::uint32_t ng = 1; ng < 400; ng += (ng < 40 ? 1 : 37))
    for (const std::uint32_t ndup : {0u, 1u, 3u, ng / 2 + 1, 2 * ng})
    {
      std::vector<std::uint32_t> sp;
      for (std::uint32_t k = 0; k < ng; ++k) sp.push_back(pos(rng));
      std::uniform_int_distribution<std::uint32_t> earlier(0, ng - 1);
      for (std::uint32_t k = 0; k < ndup; ++k) sp.push_back(sp[earlier(rng)]);  // a twin of a grid point
      const auto np = static_cast<std::uint32_t>(sp.size());
      PrimitiveSums got, want;
      std::memset(&got, 0, sizeof got);
      primitiveSums(sp.data(), ng, np, gx.data(), gy.data(), gz.data(), got);
      reference(sp.data(), ng, np, gx, gy, gz, want);
      // lane 3 (a copy of z) is not part of the result
      EXPECT_EQ(0, std::memcmp(got.lo, want.lo, 3 * sizeof(float))) << "ng " << ng << " np " << np;
      EXPECT_EQ(0, std::memcmp(got.hi, want.hi, 3 * sizeof(float))) << "ng " << ng << " np " << np;
      EXPECT_EQ(0, std::memcmp(got.centroid, want.centroid, 3 * sizeof(float))) << "ng " << ng << " np " << np;
      EXPECT_EQ(0, std::memcmp(got.m, want.m, sizeof want.m)) << "ng " << ng << " np " << np;
      EXPECT_EQ(0, std::memcmp(got.mxy, want.mxy, sizeof want.mxy)) << "ng " << ng << " np " << np;
      ++checked;
    }
  EXPECT_GT(checked, 200);
}
}  // namespace
