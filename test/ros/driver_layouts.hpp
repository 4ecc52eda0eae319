// The point layouts real drivers publish (field names, datatypes, offsets and point_step as each
// driver lays them out) and the room scan of the robustness tests in each, for the driver layout
// tests (test_driver_layouts.cpp, test_driver_layout_errors.cpp).
#pragma once

#include <sensor_msgs/PointCloud2.h>
#include <sensor_msgs/PointField.h>

#include <cmath>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

#include "../robustness/synthetic_cloud.hpp"
#include "ring_curvature/types.hpp"

namespace ring_curvature
{
namespace test
{

using PF = sensor_msgs::PointField;

// Header stamp of every test cloud: absolute times are this plus the point's offset in the sweep.
inline constexpr std::uint32_t kStampSec = 1700000000;
inline constexpr std::uint32_t kStampNsec = 123456000;
inline constexpr double kStamp = kStampSec + kStampNsec * 1e-9;

/// How a layout encodes the per-point time.
enum class TimeKind
{
  RelativeSeconds,      // float, seconds after the header stamp (velodyne_pointcloud)
  RelativeNanoseconds,  // integer, ns after the stamp (ouster-ros `t`, Livox `offset_time`)
  AbsoluteSeconds,      // float64 seconds since the epoch (Hesai, RoboSense)
  AbsoluteNanoseconds,  // float64 ns since the epoch (livox_ros_driver2)
};

struct Field
{
  const char* name;
  std::uint32_t offset;
  std::uint8_t datatype;
};

struct DriverLayout
{
  const char* driver;
  std::uint32_t point_step;
  std::vector<Field> fields;
  const char* ring;  ///< the field holding the ring index
  const char* time;  ///< the field holding the time
  TimeKind time_kind;
  double time_scale;  ///< what makeView must find with time_unit "auto"
  bool organized = false;
};

// velodyne_pointcloud PointXYZIRT, packed: unaligned float after the uint16 ring.
inline DriverLayout velodyne()
{
  return {"velodyne_pointcloud XYZIRT", 22,
          {{"x", 0, PF::FLOAT32}, {"y", 4, PF::FLOAT32}, {"z", 8, PF::FLOAT32}, {"intensity", 12, PF::FLOAT32},
           {"ring", 16, PF::UINT16}, {"time", 18, PF::FLOAT32}},
          "ring", "time", TimeKind::RelativeSeconds, 1.0};
}

// ouster-ros (ROS 1) "original" PointOS: PCL_ADD_POINT4D pads x, y, z to 16 bytes; EIGEN_ALIGN16
// rounds the 36 bytes up to 48; organized, one row per beam.
inline DriverLayout ouster()
{
  return {"ouster-ros PointOS", 48,
          {{"x", 0, PF::FLOAT32}, {"y", 4, PF::FLOAT32}, {"z", 8, PF::FLOAT32}, {"intensity", 16, PF::FLOAT32},
           {"t", 20, PF::UINT32}, {"reflectivity", 24, PF::UINT16}, {"ring", 26, PF::UINT16},
           {"ambient", 28, PF::UINT16}, {"range", 32, PF::UINT32}},
          "ring", "t", TimeKind::RelativeNanoseconds, 1e-9, true};
}

// The older ouster_ros point: ring uint8, `noise` where the newer one has `ambient`.
inline DriverLayout ousterLegacy()
{
  return {"ouster_ros legacy PointOS", 48,
          {{"x", 0, PF::FLOAT32}, {"y", 4, PF::FLOAT32}, {"z", 8, PF::FLOAT32}, {"intensity", 16, PF::FLOAT32},
           {"t", 20, PF::UINT32}, {"reflectivity", 24, PF::UINT16}, {"ring", 26, PF::UINT8},
           {"noise", 28, PF::UINT16}, {"range", 32, PF::UINT32}},
          "ring", "t", TimeKind::RelativeNanoseconds, 1e-9, true};
}

// HesaiLidar_General_ROS PointXYZIT through pcl::toROSMsg: x, y, z padded to 16, the double
// aligned to 24, the struct rounded up to 48 by EIGEN_ALIGN16.
inline DriverLayout hesaiGeneral()
{
  return {"HesaiLidar_General_ROS PointXYZIT", 48,
          {{"x", 0, PF::FLOAT32}, {"y", 4, PF::FLOAT32}, {"z", 8, PF::FLOAT32}, {"intensity", 16, PF::FLOAT32},
           {"timestamp", 24, PF::FLOAT64}, {"ring", 32, PF::UINT16}},
          "ring", "timestamp", TimeKind::AbsoluteSeconds, 1.0};
}

// HesaiLidar_ROS_2.0 and rslidar_sdk (XYZIRT) build the message field by field, packed: the
// float64 time sits unaligned at 18.
inline DriverLayout hesai2()
{
  return {"HesaiLidar_ROS_2.0 XYZIRT", 26,
          {{"x", 0, PF::FLOAT32}, {"y", 4, PF::FLOAT32}, {"z", 8, PF::FLOAT32}, {"intensity", 12, PF::FLOAT32},
           {"ring", 16, PF::UINT16}, {"timestamp", 18, PF::FLOAT64}},
          "ring", "timestamp", TimeKind::AbsoluteSeconds, 1.0};
}
inline DriverLayout robosense()
{
  DriverLayout l = hesai2();
  l.driver = "rslidar_sdk XYZIRT";
  return l;
}

// livox_ros_driver's CustomPoint copied into a PointCloud2 (the layout of the C struct: the
// uint32 after three uint8 aligned to 16): `line` is the ring, `offset_time` ns after timebase.
inline DriverLayout livoxCustom()
{
  return {"livox CustomPoint", 20,
          {{"x", 0, PF::FLOAT32}, {"y", 4, PF::FLOAT32}, {"z", 8, PF::FLOAT32}, {"reflectivity", 12, PF::UINT8},
           {"tag", 13, PF::UINT8}, {"line", 14, PF::UINT8}, {"offset_time", 16, PF::UINT32}},
          "line", "offset_time", TimeKind::RelativeNanoseconds, 1e-9};
}

// livox_ros_driver2 PointXYZRTLT, packed: `timestamp` is float64 nanoseconds since the epoch.
inline DriverLayout livox2()
{
  return {"livox_ros_driver2 XYZRTLT", 26,
          {{"x", 0, PF::FLOAT32}, {"y", 4, PF::FLOAT32}, {"z", 8, PF::FLOAT32}, {"intensity", 12, PF::FLOAT32},
           {"tag", 16, PF::UINT8}, {"line", 17, PF::UINT8}, {"timestamp", 18, PF::FLOAT64}},
          "line", "timestamp", TimeKind::AbsoluteNanoseconds, 1e-9};
}

// Autoware nebula PointXYZIRCAEDT: `channel` is the ring, `time_stamp` uint32 ns after the stamp.
inline DriverLayout nebula()
{
  return {"nebula PointXYZIRCAEDT", 32,
          {{"x", 0, PF::FLOAT32}, {"y", 4, PF::FLOAT32}, {"z", 8, PF::FLOAT32}, {"intensity", 12, PF::UINT8},
           {"return_type", 13, PF::UINT8}, {"channel", 14, PF::UINT16}, {"azimuth", 16, PF::FLOAT32},
           {"elevation", 20, PF::FLOAT32}, {"distance", 24, PF::FLOAT32}, {"time_stamp", 28, PF::UINT32}},
          "channel", "time_stamp", TimeKind::RelativeNanoseconds, 1e-9};
}

// A layout naming the ring `laser_id` (int32) with the time `t` as float64 seconds.
inline DriverLayout laserId()
{
  return {"laser_id / float64 t", 32,
          {{"x", 0, PF::FLOAT32}, {"y", 4, PF::FLOAT32}, {"z", 8, PF::FLOAT32}, {"intensity", 12, PF::FLOAT32},
           {"laser_id", 16, PF::INT32}, {"t", 24, PF::FLOAT64}},
          "laser_id", "t", TimeKind::RelativeSeconds, 1.0};
}

inline std::vector<DriverLayout> allLayouts()
{
  return {velodyne(), ouster(), ousterLegacy(), hesaiGeneral(), hesai2(), robosense(),
          livoxCustom(), livox2(), nebula(), laserId()};
}

inline ScalarType scalar(std::uint8_t datatype) { return static_cast<ScalarType>(datatype); }

inline double encodeTime(TimeKind kind, double relative_s)
{
  switch (kind)
  {
    case TimeKind::RelativeSeconds: return relative_s;
    case TimeKind::RelativeNanoseconds: return std::round(relative_s * 1e9);
    case TimeKind::AbsoluteSeconds: return kStamp + relative_s;
    case TimeKind::AbsoluteNanoseconds: return std::round((kStampSec + relative_s) * 1e9) + kStampNsec;
  }
  return 0;
}

inline constexpr int kRings = 16, kSamples = 900;  // unorganized frames, in firing order
inline constexpr int kOrganizedRings = 32, kOrganizedSamples = 1024;

inline std::vector<SyntheticPoint> pointsFor(const DriverLayout& l)
{
  if (l.organized)
    return toOrganized(roomScan(kOrganizedRings, kOrganizedSamples), kOrganizedRings, kOrganizedSamples);
  return roomScan(kRings, kSamples);
}

/// The room scan in `l`, every byte as the driver would write it (padding garbage, other fields
/// filled with a constant).
inline sensor_msgs::PointCloud2 build(const DriverLayout& l)
{
  const std::vector<SyntheticPoint> pts = pointsFor(l);
  sensor_msgs::PointCloud2 msg;
  msg.header.stamp.sec = kStampSec;
  msg.header.stamp.nsec = kStampNsec;
  msg.header.frame_id = "lidar";
  msg.height = l.organized ? kOrganizedRings : 1;
  msg.width = static_cast<std::uint32_t>(pts.size() / msg.height);
  msg.point_step = l.point_step;
  msg.row_step = msg.width * l.point_step;
  msg.is_bigendian = false;
  msg.is_dense = false;
  for (const Field& f : l.fields)
  {
    PF pf;
    pf.name = f.name;
    pf.offset = f.offset;
    pf.datatype = f.datatype;
    pf.count = 1;
    msg.fields.push_back(pf);
  }
  msg.data.assign(static_cast<std::size_t>(msg.row_step) * msg.height, 0xA5);
  for (std::size_t i = 0; i < pts.size(); ++i)
  {
    std::uint8_t* rec = msg.data.data() + i * l.point_step;
    const SyntheticPoint& p = pts[i];
    for (const Field& f : l.fields)
    {
      const std::string name = f.name;
      double v = 7.0;
      if (name == "x") v = p.x;
      else if (name == "y") v = p.y;
      else if (name == "z") v = p.z;
      else if (name == "intensity") v = p.intensity;
      else if (name == l.ring) v = static_cast<double>(p.ring);
      else if (name == l.time) v = encodeTime(l.time_kind, p.time);
      writeScalar(rec + f.offset, scalar(f.datatype), v);
    }
  }
  return msg;
}

inline const Field& fieldOf(const DriverLayout& l, const char* name)
{
  for (const Field& f : l.fields)
    if (std::string(f.name) == name)
      return f;
  throw std::runtime_error(std::string("layout has no field ") + name);
}

inline bool contains(const std::string& s, const std::string& part) { return s.find(part) != std::string::npos; }

}  // namespace test
}  // namespace ring_curvature
