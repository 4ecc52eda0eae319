// Paper Table 1 / Figure 4 as a CSV: the max error of the discrete geodesic curvature (Eq 6-9)
// against the exact curvature of the continuous trace on the cone, for dtheta = pi/32 .. pi/512.
// The traces, the reference curvature and the sampling are those of test/core/test_convergence.cpp
// (float64 input, the core's Pipeline), so the figure shows what that test asserts. The paper's
// z-plane formula on the tilted ground is added for contrast: it converges to another quantity.
//
//   convergence_table > table.csv
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <vector>

#include "support/convergence_study.hpp"

using namespace ring_curvature;
using namespace ring_curvature::test;

namespace
{
constexpr double kPi = 3.14159265358979323846;

template <typename Trace>
void table(const char* shape, const char* formula, const Trace& tr, double th0, double th1, CurvatureMode mode)
{
  double prev = std::numeric_limits<double>::quiet_NaN();
  for (int div = 32; div <= 512; div *= 2)
  {
    const ConvergenceRow r = measureConvergence(tr, th0, th1, kPi / div, mode);
    // EOC = log2(e(2h) / e(h)): the observed order of convergence between successive halvings.
    const double eoc = std::isnan(prev) ? std::numeric_limits<double>::quiet_NaN() : std::log2(prev / r.max_error);
    std::printf("%s,%s,pi/%d,%.10g,%zu,%.6e,", shape, formula, div, kPi / div, r.points, r.max_error);
    if (std::isnan(eoc))
      std::printf("\n");
    else
      std::printf("%.3f\n", eoc);
    prev = r.max_error;
  }
}
}  // namespace

int main()
{
  std::printf("shape,formula,dtheta,dtheta_rad,K,max_error,eoc\n");
  // The same three traces as test_convergence.cpp (test/support/convergence_study.hpp).
  table("cylinder R=6 a=1.5 phi=-10", "developed", studyCylinder(), 0.0, 2 * kPi, CurvatureMode::Developed);
  table("wall d=5 phi=+7", "developed", studyWall(), kWallYaw - kPi / 3, kWallYaw + kPi / 3, CurvatureMode::Developed);
  const PlaneTrace ground = studyGround();
  table("ground h=1.8 pitch=5 phi=-15", "developed", ground, 0.0, 2 * kPi, CurvatureMode::Developed);
  table("ground h=1.8 pitch=5 phi=-15", "z-plane (paper Eq 9)", ground, 0.0, 2 * kPi, CurvatureMode::Paper);
  return 0;
}
