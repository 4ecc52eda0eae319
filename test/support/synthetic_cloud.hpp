// Builds clouds for the core tests in velodyne_pointcloud's packed 22-byte XYZIRT layout
// (x, y, z, intensity float32; ring uint16 at 16; time float32 at 18), or with float64 x, y, z
// (34-byte records) where a test needs more than float32 precision; read through a
// PointCloudView exactly as the nodelet reads a PointCloud2.
#pragma once

#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <vector>

#include "ring_curvature/types.hpp"

namespace ring_curvature
{
namespace test
{

class SyntheticCloud
{
public:
  explicit SyntheticCloud(bool float64 = false)
      : f64_(float64), step_(float64 ? 34u : 22u), rest_(float64 ? 24 : 12)
  {
  }

  void add(double x, double y, double z, int ring, float time = 0.0f)
  {
    std::uint8_t rec[34] = {};
    if (f64_)
    {
      const double d[3] = {x, y, z};
      std::memcpy(rec, d, sizeof d);
    }
    else
    {
      const float f[3] = {static_cast<float>(x), static_cast<float>(y), static_cast<float>(z)};
      std::memcpy(rec, f, sizeof f);
    }
    const float intensity = 100.0f;
    const std::uint16_t r = static_cast<std::uint16_t>(ring);
    std::memcpy(rec + rest_, &intensity, 4);
    std::memcpy(rec + rest_ + 4, &r, 2);
    std::memcpy(rec + rest_ + 6, &time, 4);
    data_.insert(data_.end(), rec, rec + step_);
  }
  void addNaN(int ring)
  {
    const double nan = std::numeric_limits<double>::quiet_NaN();
    add(nan, nan, nan, ring);
  }
  /// Overwrites point i's time field (float32 seconds).
  void setTime(std::size_t i, float time) { std::memcpy(data_.data() + i * step_ + rest_ + 6, &time, 4); }
  /// Overwrites point i's time field with a uint32 (read it as such: view.time.type = UInt32).
  void setTimeUInt32(std::size_t i, std::uint32_t time) { std::memcpy(data_.data() + i * step_ + rest_ + 6, &time, 4); }
  std::size_t size() const { return data_.size() / step_; }
  std::uint32_t pointStep() const { return step_; }
  std::vector<std::uint8_t>& bytes() { return data_; }
  const std::vector<std::uint8_t>& bytes() const { return data_; }

  /// View of the cloud; organized as `height` rows when height > 1.
  PointCloudView view(std::uint32_t height = 1) const
  {
    PointCloudView v;
    v.data = data_.data();
    v.data_size = data_.size();
    v.height = size() == 0 ? 0 : height;
    v.width = height == 0 || size() == 0 ? 0 : static_cast<std::uint32_t>(size() / height);
    v.point_step = step_;
    v.row_step = v.width * step_;
    const ScalarType ct = f64_ ? ScalarType::Float64 : ScalarType::Float32;
    const std::int64_t cs = f64_ ? 8 : 4;
    v.x = {0, ct};
    v.y = {cs, ct};
    v.z = {2 * cs, ct};
    v.intensity = {rest_, ScalarType::Float32};
    v.ring = {rest_ + 4, ScalarType::UInt16};
    v.time = {rest_ + 6, ScalarType::Float32};
    return v;
  }

private:
  bool f64_;
  std::uint32_t step_;
  std::int64_t rest_;  // offset of intensity; ring and time follow
  std::vector<std::uint8_t> data_;
};

/// Unit direction of a beam at elevation phi, azimuth theta.
inline void beamDir(double phi, double th, double& dx, double& dy, double& dz)
{
  dx = std::cos(phi) * std::cos(th);
  dy = std::cos(phi) * std::sin(th);
  dz = std::sin(phi);
}

}  // namespace test
}  // namespace ring_curvature
