// The convergence study of the paper's Table 1, shared by the gtest (test/core/test_convergence.cpp,
// which asserts on it) and the figure tool (tools/convergence_table.cpp, which prints it): one
// analytic trace sampled at a given azimuth step, run through the core's Pipeline, and the
// largest error against the exact geodesic curvature of the continuous trace.
#pragma once

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include "cone_curves.hpp"
#include "ring_curvature/pipeline.hpp"
#include "synthetic_cloud.hpp"

namespace ring_curvature
{
namespace test
{

constexpr double kStudyPi = 3.14159265358979323846;

struct ConvergenceRow
{
  double dtheta = 0;
  std::size_t points = 0;   ///< samples on the ring
  std::size_t defined = 0;  ///< samples whose curvature the pipeline defined
  double max_error = std::numeric_limits<double>::quiet_NaN();
  Status status;            ///< the pipeline's verdict on the frame
};

/// Samples `tr` on [th0, th1) every `dth` (a closed ring when that is the full circle) as a
/// float64 cloud (float32 rounding would dominate below pi/128) and measures `mode`.
template <typename Trace>
ConvergenceRow measureConvergence(const Trace& tr, double th0, double th1, double dth, CurvatureMode mode)
{
  SyntheticCloud cloud(/*float64=*/true);
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
  ConvergenceRow row;
  row.dtheta = dth;
  row.points = thetas.size();
  row.status = pipe.process(cloud.view(), res);
  if (!row.status) return row;
  double worst = 0;
  for (std::size_t i = 0; i < thetas.size(); ++i)
  {
    if (!std::isfinite(res.curvature[i])) continue;
    ++row.defined;
    worst = std::max(worst, std::fabs(res.curvature[i] - geodesicCurvature(tr, thetas[i])));
  }
  row.max_error = worst;
  return row;
}

/// The three traces of the study: a vertical cylinder seen from inside, off its axis (a closed,
/// non-circular ring); a wall; the ground under a 5 deg pitch (level ground traces an exact
/// circle, for which Eq 9 is exact at every step: no test at all).
inline CylinderTrace studyCylinder() { return {6.0, 1.5, -10.0 * kStudyPi / 180}; }
constexpr double kWallYaw = 20.0 * kStudyPi / 180;
inline PlaneTrace studyWall() { return {std::cos(kWallYaw), std::sin(kWallYaw), 0.0, 5.0, 7.0 * kStudyPi / 180}; }
inline PlaneTrace studyGround()
{
  const double b = 5.0 * kStudyPi / 180;
  return {std::sin(b), 0.0, -std::cos(b), 1.8, -15.0 * kStudyPi / 180};
}

}  // namespace test
}  // namespace ring_curvature
