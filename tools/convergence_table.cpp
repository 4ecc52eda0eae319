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

#include "ring_curvature/pipeline.hpp"
#include "support/cone_curves.hpp"
#include "support/synthetic_cloud.hpp"

using namespace ring_curvature;
using namespace ring_curvature::test;

namespace
{
constexpr double kPi = 3.14159265358979323846;

struct Row
{
  std::size_t points = 0;
  double max_error = std::numeric_limits<double>::quiet_NaN();
};

// One closed or open ring sampled at step dth on [th0, th1); max |kappa - kappa_exact| over the
// samples whose curvature is defined. NaN error when the pipeline rejects the frame.
template <typename Trace>
Row measure(const Trace& tr, double th0, double th1, double dth, CurvatureMode mode)
{
  SyntheticCloud cloud(/*float64=*/true);  // float32 rounding would dominate below pi/128
  std::vector<double> thetas;
  for (double th = th0; th < th1 - 1e-9; th += dth)
  {
    const RangeDerivs r = tr.at(th);
    double dx, dy, dz;
    beamDir(tr.phi, th, dx, dy, dz);
    cloud.add(r.rho * dx, r.rho * dy, r.rho * dz, 0);
    thetas.push_back(th);
  }
  Params p;
  p.curvature_mode = mode;
  p.max_range = 1000;
  Pipeline pipe(p);
  FrameResult res;
  Row row;
  row.points = thetas.size();
  if (!pipe.process(cloud.view(), res))
    return row;
  double worst = 0;
  for (std::size_t i = 0; i < thetas.size(); ++i)
    if (std::isfinite(res.curvature[i]))
      worst = std::max(worst, std::fabs(res.curvature[i] - geodesicCurvature(tr, thetas[i])));
  row.max_error = worst;
  return row;
}

template <typename Trace>
void table(const char* shape, const char* formula, const Trace& tr, double th0, double th1, CurvatureMode mode)
{
  double prev = std::numeric_limits<double>::quiet_NaN();
  for (int div = 32; div <= 512; div *= 2)
  {
    const Row r = measure(tr, th0, th1, kPi / div, mode);
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
  // Same three traces as test_convergence.cpp.
  table("cylinder R=6 a=1.5 phi=-10", "developed", CylinderTrace{6.0, 1.5, -10.0 * kPi / 180}, 0.0, 2 * kPi,
        CurvatureMode::Developed);
  const double a = 20.0 * kPi / 180;
  table("wall d=5 phi=+7", "developed", PlaneTrace{std::cos(a), std::sin(a), 0.0, 5.0, 7.0 * kPi / 180}, a - kPi / 3,
        a + kPi / 3, CurvatureMode::Developed);
  const double b = 5.0 * kPi / 180;
  const PlaneTrace ground{std::sin(b), 0.0, -std::cos(b), 1.8, -15.0 * kPi / 180};
  table("ground h=1.8 pitch=5 phi=-15", "developed", ground, 0.0, 2 * kPi, CurvatureMode::Developed);
  table("ground h=1.8 pitch=5 phi=-15", "z-plane (paper Eq 9)", ground, 0.0, 2 * kPi, CurvatureMode::Paper);
  return 0;
}
