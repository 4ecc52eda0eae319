// Motion compensation of one sweep: every point moved from where the sensor was when it fired to
// where it was at a reference time (the cloud's stamp), assuming constant velocity over the sweep
// (as LOAM and KISS-ICP do). A-LOAM's odometry and mapping take points as if fired all at once; in a turn
// a sweep's two ends then disagree by the turn's angle times the range.
#pragma once

#include <array>
#include <cstddef>

namespace ring_curvature
{

/// The sensor's motion over one sweep: its pose at the sweep's end in the frame of its start.
struct SweepMotion
{
  std::array<double, 3> rotation{};     ///< axis times angle [rad]
  std::array<double, 3> translation{};  ///< [m]
};

class SweepDeskew
{
public:
  /// Tables the motion from `reference` seconds into a sweep of `period` seconds to every time in
  /// it (fixed size: no allocation).
  void prepare(const SweepMotion& motion, double period, double reference = 0.0);
  /// (x, y, z), fired `t` seconds into the sweep, in the sensor frame at the reference time.
  void apply(float t, float& x, float& y, float& z) const
  {
    const float f = t * steps_per_second_;
    // (a NaN time, from a NaN in the time field, takes the first entry: no out-of-range index)
    const int k = !(f > 0.0f) ? 0 : (f >= static_cast<float>(kSteps) ? kSteps : static_cast<int>(f + 0.5f));
    const std::array<float, 12>& m = table_[static_cast<std::size_t>(k)];
    const float px = x, py = y, pz = z;
    x = m[0] * px + m[1] * py + m[2] * pz + m[9];
    y = m[3] * px + m[4] * py + m[5] * pz + m[10];
    z = m[6] * px + m[7] * py + m[8] * pz + m[11];
  }

private:
  // 1/1024 of a sweep: a 0.1 rad turn per sweep is then off by at most 5e-5 rad (5 mm at 100 m).
  static constexpr int kSteps = 1024;
  std::array<std::array<float, 12>, kSteps + 1> table_{};  // row-major R, then t
  float steps_per_second_ = 0.0f;
};

}  // namespace ring_curvature
