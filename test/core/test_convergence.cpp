// Paper Table 1: the discrete geodesic curvature (Eq 6-9) converges at first order in the
// azimuth step. The reference is the curvature of the exact continuous trace on the cone,
// derived in test/support/cone_curves.hpp independently of the code under test.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "../support/convergence_study.hpp"
#include "common/float_bits.hpp"

using namespace ring_curvature;
using namespace ring_curvature::test;

namespace
{
constexpr double kPi = 3.14159265358979323846;

using Row = ConvergenceRow;

template <typename Trace>
Row measure(const Trace& tr, double th0, double th1, double dth, CurvatureMode mode)
{
  const Row row = measureConvergence(tr, th0, th1, dth, mode);
  EXPECT_TRUE(row.status.ok) << row.status.message;
  EXPECT_GE(row.defined + 2, row.points) << "curvature undefined at interior samples";
  return row;
}

template <typename Trace>
void expectFirstOrder(const char* name, const Trace& tr, double th0, double th1)
{
  std::vector<Row> rows;
  for (int div = 32; div <= 512; div *= 2) rows.push_back(measure(tr, th0, th1, kPi / div, CurvatureMode::Developed));
  std::printf("\n%-28s %-10s %8s %14s %6s\n", name, "dtheta", "K", "max error", "EOC");
  for (std::size_t i = 0; i < rows.size(); ++i)
  {
    const double eoc = i == 0 ? NAN : std::log(rows[i - 1].max_error / rows[i].max_error) / std::log(2.0);
    std::printf("%-28s pi/%-7d %8zu %14.4e %6s\n", "", static_cast<int>(std::lround(kPi / rows[i].dtheta)),
                rows[i].points, rows[i].max_error, i == 0 ? "-" : std::to_string(eoc).substr(0, 5).c_str());
    if (i > 0)
    {
      EXPECT_GE(eoc, 0.9) << name << " at pi/" << std::lround(kPi / rows[i].dtheta);
      EXPECT_LE(eoc, 1.1) << name << " at pi/" << std::lround(kPi / rows[i].dtheta);
    }
  }
  // and the error itself is small at the finest step (relative to the curvature scale)
  EXPECT_LT(rows.back().max_error, 0.01 * std::fabs(geodesicCurvature(tr, 0.5 * (th0 + th1))) + 1e-3);
}
}  // namespace

TEST(Convergence, CylinderOffAxis)
{
  // sensor 1.5 m off the axis of a 6 m radius tank, beam at -10 deg: a closed, non-circular ring
  expectFirstOrder("cylinder R=6 a=1.5 phi=-10", studyCylinder(), 0.0, 2 * kPi);
}

TEST(Convergence, VerticalPlane)
{
  expectFirstOrder("wall d=5 phi=+7", studyWall(), kWallYaw - kPi / 3, kWallYaw + kPi / 3);
}

TEST(Convergence, TiltedGround)
{
  expectFirstOrder("ground h=1.8 pitch=5 phi=-15", studyGround(), 0.0, 2 * kPi);
}

TEST(Convergence, PaperZPlaneFormulaMissesTheConeAtNonZeroElevation)
{
  // READING_NOTES 1: Eq 9 taken in the z-plane converges to a different quantity when phi != 0;
  // on the same tilted ground the developed-plane error keeps shrinking, the z-plane one stalls.
  const PlaneTrace g = studyGround();
  const Row dev = measure(g, 0.0, 2 * kPi, kPi / 512, CurvatureMode::Developed);
  const Row zpl = measure(g, 0.0, 2 * kPi, kPi / 512, CurvatureMode::Paper);
  std::printf("\nground at pi/512: developed max error %.3e, z-plane (paper) max error %.3e\n", dev.max_error,
              zpl.max_error);
  EXPECT_GT(zpl.max_error, 5 * dev.max_error);
}

// A ring so coarse that the chords turn by more than the small-angle polynomial covers (a
// hexagon: 60 deg between samples, one-sample chords): the features must switch to libm's sine
// and cosine for the ring (the polynomial's cosine is off by 3.6e-5 at 60 deg, which makes the
// chords 3.6e-5 too long). The chord length, turning / curvature, is then the hexagon's side
// to within what the float azimuths allow (fastAtan2, ~1e-5 rad: at most 7e-6 here); the
// turning angle carries fastAtan2's error too.
TEST(Convergence, CoarseRingBeyondThePolynomialRangeTakesLibm)
{
  constexpr double kPiD = 3.14159265358979323846;
  for (const int k : {6, 8})
  {
    const double radius = 2.0;
    SyntheticCloud cloud(true);  // float64: the coordinates are exact
    for (int j = 0; j < k; ++j)
    {
      const double th = 2.0 * kPiD * j / k;
      cloud.add(radius * std::cos(th), radius * std::sin(th), 0.0, 0);
    }
    Params params;  // chord mode: at 2 m the 0.25 m chord is one sample
    Pipeline pipe(params);
    FrameResult res;
    ASSERT_TRUE(pipe.process(cloud.view(), res).ok);
    const Features& f = pipe.features();
    ASSERT_EQ(f.curvature.size(), static_cast<std::size_t>(k));
    const double side = 2.0 * radius * std::sin(kPiD / k), turn = 2.0 * kPiD / k;
    for (int j = 0; j < k; ++j)
    {
      ASSERT_TRUE(std::isfinite(f.curvature[j]) && f.curvature[j] > 0) << "k " << k << " sample " << j;
      const double len = static_cast<double>(f.turning[j]) / f.curvature[j];
      EXPECT_NEAR(len / side, 1.0, 1.5e-5) << "k " << k << " sample " << j;
      EXPECT_NEAR(f.turning[j], turn, 3e-5) << "k " << k << " sample " << j;
    }
  }
}
