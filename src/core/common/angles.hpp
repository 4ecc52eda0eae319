// Angle constants and wraps shared by the core's files. Azimuths are float32; the float
// constants are the nearest floats (2 * kPi and kTwoPi are the same float), and wrapPi<double>
// serves the double modes.
#pragma once

#include <cmath>

namespace ring_curvature
{

constexpr double kPiD = 3.14159265358979323846;
constexpr float kPi = static_cast<float>(kPiD);
constexpr float kTwoPi = static_cast<float>(2 * kPiD);

/// An angle difference in (-3 pi, 3 pi) brought into [-pi, pi), by selections so that calling loops
/// vectorize (-fno-trapping-math lets both sides be formed). Float or double.
template <class T>
inline T wrapPi(T a)
{
  const T pi = static_cast<T>(kPiD), two_pi = static_cast<T>(2 * kPiD);
  a = a >= pi ? a - two_pi : a;
  a = a < -pi ? a + two_pi : a;
  return a;
}

/// The distance on the circle of two azimuths d apart (|d| < 2 pi): |d| or 2 pi - |d|.
inline float circularDistance(float d)
{
  const float a = std::fabs(d);
  return a > kPi ? kTwoPi - a : a;
}

}  // namespace ring_curvature
