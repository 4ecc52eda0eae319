// Analytic scan rings for the convergence study (issue 3, paper Table 1): the trace of a beam of
// elevation phi on a plane or a vertical cylinder, rho(theta) in closed form with exact first and
// second derivatives, and the geodesic curvature of that trace on the cone, derived here
// independently of the code under test: the cone develops isometrically onto the plane as
// w = rho e^{i psi}, psi = theta cos(phi), whose curvature in polar form is
//   kappa = (r^2 + 2 r'^2 - r r'') / (r^2 + r'^2)^{3/2},  r' = d rho / d psi.
#pragma once

#include <cmath>

namespace ring_curvature
{
namespace test
{

struct RangeDerivs
{
  double rho, d1, d2;  // rho(theta), d rho / d theta, d2 rho / d theta2
};

/// Plane n . p = d (|n| = 1, d > 0) seen by a beam of elevation phi: rho = d / (n . u(theta)),
/// u = (cos phi cos theta, cos phi sin theta, sin phi).
struct PlaneTrace
{
  double nx, ny, nz, d, phi;
  RangeDerivs at(double th) const
  {
    const double c = std::cos(phi), s = std::sin(phi);
    const double g = c * (nx * std::cos(th) + ny * std::sin(th)) + nz * s;
    const double g1 = c * (-nx * std::sin(th) + ny * std::cos(th));
    const double g2 = -c * (nx * std::cos(th) + ny * std::sin(th));
    return {d / g, -d * g1 / (g * g), d * (2 * g1 * g1 - g * g2) / (g * g * g)};
  }
};

/// Vertical cylinder of radius R around (a, 0), sensor inside (|a| < R): the horizontal range
/// h(theta) = a cos theta + sqrt(R^2 - a^2 sin^2 theta), and rho = h / cos(phi).
struct CylinderTrace
{
  double R, a, phi;
  RangeDerivs at(double th) const
  {
    const double c = std::cos(phi);
    const double s = std::sin(th), co = std::cos(th);
    const double q = R * R - a * a * s * s;
    const double sq = std::sqrt(q);
    const double q1 = -2 * a * a * s * co;
    const double q2 = -2 * a * a * (co * co - s * s);
    const double h = a * co + sq;
    const double h1 = -a * s + q1 / (2 * sq);
    const double h2 = -a * co + (2 * q * q2 - q1 * q1) / (4 * q * sq);
    return {h / c, h1 / c, h2 / c};
  }
};

/// Geodesic curvature of the trace on the cone of elevation phi, at azimuth theta.
template <typename Trace>
double geodesicCurvature(const Trace& t, double th)
{
  const RangeDerivs r = t.at(th);
  const double c = std::cos(t.phi);
  const double r1 = r.d1 / c, r2 = r.d2 / (c * c);  // derivatives with respect to psi = theta cos(phi)
  return std::fabs(r.rho * r.rho + 2 * r1 * r1 - r.rho * r2) / std::pow(r.rho * r.rho + r1 * r1, 1.5);
}

}  // namespace test
}  // namespace ring_curvature
