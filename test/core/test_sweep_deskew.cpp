// SweepDeskew: points moved to the sensor frame at the reference time under constant velocity.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "ring_curvature/sweep_deskew.hpp"

using ring_curvature::SweepDeskew;
using ring_curvature::SweepMotion;

namespace
{
constexpr double kPeriod = 0.1;

// A static world point seen by a sensor that moves with `motion` per sweep: where the sensor sees
// it at sweep fraction s (its pose then is exp(s * motion) in the start frame; yaw only here).
void seenAt(const SweepMotion& motion, double s, double wx, double wy, double wz, float& x, float& y, float& z)
{
  const double yaw = s * motion.rotation[2];
  const double tx = s * motion.translation[0], ty = s * motion.translation[1], tz = s * motion.translation[2];
  const double dx = wx - tx, dy = wy - ty, dz = wz - tz;  // R(yaw)^T (w - t)
  x = static_cast<float>(std::cos(yaw) * dx + std::sin(yaw) * dy);
  y = static_cast<float>(-std::sin(yaw) * dx + std::cos(yaw) * dy);
  z = static_cast<float>(dz);
}
}  // namespace

TEST(SweepDeskew, StaticSensorLeavesPointsAsTheyAre)
{
  SweepDeskew d;
  d.prepare(SweepMotion{}, kPeriod);
  float x = 3.5f, y = -2.0f, z = 0.25f;
  d.apply(0.07f, x, y, z);
  EXPECT_FLOAT_EQ(x, 3.5f);
  EXPECT_FLOAT_EQ(y, -2.0f);
  EXPECT_FLOAT_EQ(z, 0.25f);
}

TEST(SweepDeskew, TurningAndDrivingSensorSeesOneWorldAfterDeskew)
{
  // 6 m/s forward and 0.5 rad/s yaw at 10 Hz: a turn, where one sweep's two ends disagree by ~1 m at 20 m
  SweepMotion motion;
  motion.rotation = {0.0, 0.0, 0.05};
  motion.translation = {0.6, 0.02, 0.0};
  for (const double reference : {0.0, 0.05, 0.1})  // the stamp at the start, middle or end of the sweep
  {
    SweepDeskew d;
    d.prepare(motion, kPeriod, reference);
    const double sr = reference / kPeriod;
    double worst = 0.0, worst_raw = 0.0;
    for (int i = 0; i <= 20; ++i)
    {
      const double s = i / 20.0, az = 6.283 * s;
      const double wx = 20.0 * std::cos(az), wy = 20.0 * std::sin(az), wz = -1.5;
      float x, y, z, rx, ry, rz;
      seenAt(motion, s, wx, wy, wz, x, y, z);
      seenAt(motion, sr, wx, wy, wz, rx, ry, rz);  // where the sensor at the reference time sees it
      const double raw = std::hypot(x - rx, y - ry, z - rz);
      d.apply(static_cast<float>(s * kPeriod), x, y, z);
      worst = std::max(worst, static_cast<double>(std::hypot(x - rx, y - ry, z - rz)));
      worst_raw = std::max(worst_raw, raw);
    }
    // (float tables in 1/1024 sweep steps: millimetres)
    EXPECT_LT(worst, 0.005) << "reference " << reference;
    EXPECT_GT(worst_raw, 0.5) << "reference " << reference;
  }
}

TEST(SweepDeskew, TimesOutsideTheSweepAreClamped)
{
  SweepMotion motion;
  motion.translation = {1.0, 0.0, 0.0};
  SweepDeskew d;
  d.prepare(motion, kPeriod);
  float x = 0, y = 0, z = 0;
  d.apply(0.5f, x, y, z);  // beyond the sweep: as at its end, not extrapolated
  EXPECT_NEAR(x, 1.0f, 1e-6);
  x = 0;
  d.apply(-0.5f, x, y, z);
  EXPECT_NEAR(x, 0.0f, 1e-6);
  x = 0;
  d.apply(std::numeric_limits<float>::quiet_NaN(), x, y, z);  // as at the sweep's start
  EXPECT_NEAR(x, 0.0f, 1e-6);
  x = 0;
  d.apply(std::numeric_limits<float>::infinity(), x, y, z);  // as at its end
  EXPECT_NEAR(x, 1.0f, 1e-6);
}
