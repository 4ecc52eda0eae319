// The adapter against the point layouts real drivers publish (field names, datatypes, offsets and
// point_step as each driver lays them out), and the parameters that name the ring and time fields
// (ring_field, time_field, time_unit). The geometry is the synthetic room scan of the robustness
// tests, so every layout carries the same points and must give the same labels.
#include <gtest/gtest.h>
#include <sensor_msgs/PointField.h>

#include <cmath>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "../robustness/synthetic_cloud.hpp"
#include "ring_curvature/pipeline.hpp"
#include "ring_curvature/ros/cloud_adapter.hpp"
#include "ring_curvature/ros/frame_processor.hpp"
#include "ring_curvature/ros/param_loading.hpp"

using namespace ring_curvature;
using PF = sensor_msgs::PointField;

namespace
{

// Header stamp of every test cloud: absolute times are this plus the point's offset in the sweep.
constexpr std::uint32_t kStampSec = 1700000000;
constexpr std::uint32_t kStampNsec = 123456000;
constexpr double kStamp = kStampSec + kStampNsec * 1e-9;

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
DriverLayout velodyne()
{
  return {"velodyne_pointcloud XYZIRT", 22,
          {{"x", 0, PF::FLOAT32}, {"y", 4, PF::FLOAT32}, {"z", 8, PF::FLOAT32}, {"intensity", 12, PF::FLOAT32},
           {"ring", 16, PF::UINT16}, {"time", 18, PF::FLOAT32}},
          "ring", "time", TimeKind::RelativeSeconds, 1.0};
}

// ouster-ros (ROS 1) "original" PointOS: PCL_ADD_POINT4D pads x, y, z to 16 bytes; EIGEN_ALIGN16
// rounds the 36 bytes up to 48; organized, one row per beam.
DriverLayout ouster()
{
  return {"ouster-ros PointOS", 48,
          {{"x", 0, PF::FLOAT32}, {"y", 4, PF::FLOAT32}, {"z", 8, PF::FLOAT32}, {"intensity", 16, PF::FLOAT32},
           {"t", 20, PF::UINT32}, {"reflectivity", 24, PF::UINT16}, {"ring", 26, PF::UINT16},
           {"ambient", 28, PF::UINT16}, {"range", 32, PF::UINT32}},
          "ring", "t", TimeKind::RelativeNanoseconds, 1e-9, true};
}

// The older ouster_ros point: ring uint8, `noise` where the newer one has `ambient`.
DriverLayout ousterLegacy()
{
  return {"ouster_ros legacy PointOS", 48,
          {{"x", 0, PF::FLOAT32}, {"y", 4, PF::FLOAT32}, {"z", 8, PF::FLOAT32}, {"intensity", 16, PF::FLOAT32},
           {"t", 20, PF::UINT32}, {"reflectivity", 24, PF::UINT16}, {"ring", 26, PF::UINT8},
           {"noise", 28, PF::UINT16}, {"range", 32, PF::UINT32}},
          "ring", "t", TimeKind::RelativeNanoseconds, 1e-9, true};
}

// HesaiLidar_General_ROS PointXYZIT through pcl::toROSMsg: x, y, z padded to 16, the double
// aligned to 24, the struct rounded up to 48 by EIGEN_ALIGN16.
DriverLayout hesaiGeneral()
{
  return {"HesaiLidar_General_ROS PointXYZIT", 48,
          {{"x", 0, PF::FLOAT32}, {"y", 4, PF::FLOAT32}, {"z", 8, PF::FLOAT32}, {"intensity", 16, PF::FLOAT32},
           {"timestamp", 24, PF::FLOAT64}, {"ring", 32, PF::UINT16}},
          "ring", "timestamp", TimeKind::AbsoluteSeconds, 1.0};
}

// HesaiLidar_ROS_2.0 and rslidar_sdk (XYZIRT) build the message field by field, packed: the
// float64 time sits unaligned at 18.
DriverLayout hesai2()
{
  return {"HesaiLidar_ROS_2.0 XYZIRT", 26,
          {{"x", 0, PF::FLOAT32}, {"y", 4, PF::FLOAT32}, {"z", 8, PF::FLOAT32}, {"intensity", 12, PF::FLOAT32},
           {"ring", 16, PF::UINT16}, {"timestamp", 18, PF::FLOAT64}},
          "ring", "timestamp", TimeKind::AbsoluteSeconds, 1.0};
}
DriverLayout robosense()
{
  DriverLayout l = hesai2();
  l.driver = "rslidar_sdk XYZIRT";
  return l;
}

// livox_ros_driver's CustomPoint copied into a PointCloud2 (the layout of the C struct: the
// uint32 after three uint8 aligned to 16): `line` is the ring, `offset_time` ns after timebase.
DriverLayout livoxCustom()
{
  return {"livox CustomPoint", 20,
          {{"x", 0, PF::FLOAT32}, {"y", 4, PF::FLOAT32}, {"z", 8, PF::FLOAT32}, {"reflectivity", 12, PF::UINT8},
           {"tag", 13, PF::UINT8}, {"line", 14, PF::UINT8}, {"offset_time", 16, PF::UINT32}},
          "line", "offset_time", TimeKind::RelativeNanoseconds, 1e-9};
}

// livox_ros_driver2 PointXYZRTLT, packed: `timestamp` is float64 nanoseconds since the epoch.
DriverLayout livox2()
{
  return {"livox_ros_driver2 XYZRTLT", 26,
          {{"x", 0, PF::FLOAT32}, {"y", 4, PF::FLOAT32}, {"z", 8, PF::FLOAT32}, {"intensity", 12, PF::FLOAT32},
           {"tag", 16, PF::UINT8}, {"line", 17, PF::UINT8}, {"timestamp", 18, PF::FLOAT64}},
          "line", "timestamp", TimeKind::AbsoluteNanoseconds, 1e-9};
}

// Autoware nebula PointXYZIRCAEDT: `channel` is the ring, `time_stamp` uint32 ns after the stamp.
DriverLayout nebula()
{
  return {"nebula PointXYZIRCAEDT", 32,
          {{"x", 0, PF::FLOAT32}, {"y", 4, PF::FLOAT32}, {"z", 8, PF::FLOAT32}, {"intensity", 12, PF::UINT8},
           {"return_type", 13, PF::UINT8}, {"channel", 14, PF::UINT16}, {"azimuth", 16, PF::FLOAT32},
           {"elevation", 20, PF::FLOAT32}, {"distance", 24, PF::FLOAT32}, {"time_stamp", 28, PF::UINT32}},
          "channel", "time_stamp", TimeKind::RelativeNanoseconds, 1e-9};
}

// A layout naming the ring `laser_id` (int32) with the time `t` as float64 seconds.
DriverLayout laserId()
{
  return {"laser_id / float64 t", 32,
          {{"x", 0, PF::FLOAT32}, {"y", 4, PF::FLOAT32}, {"z", 8, PF::FLOAT32}, {"intensity", 12, PF::FLOAT32},
           {"laser_id", 16, PF::INT32}, {"t", 24, PF::FLOAT64}},
          "laser_id", "t", TimeKind::RelativeSeconds, 1.0};
}

std::vector<DriverLayout> allLayouts()
{
  return {velodyne(), ouster(), ousterLegacy(), hesaiGeneral(), hesai2(), robosense(),
          livoxCustom(), livox2(), nebula(), laserId()};
}

ScalarType scalar(std::uint8_t datatype) { return static_cast<ScalarType>(datatype); }

double encodeTime(TimeKind kind, double relative_s)
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

constexpr int kRings = 16, kSamples = 900;           // unorganized frames, in firing order
constexpr int kOrganizedRings = 32, kOrganizedSamples = 1024;

std::vector<test::SyntheticPoint> pointsFor(const DriverLayout& l)
{
  if (l.organized)
    return test::toOrganized(test::roomScan(kOrganizedRings, kOrganizedSamples), kOrganizedRings, kOrganizedSamples);
  return test::roomScan(kRings, kSamples);
}

/// The room scan in `l`, every byte as the driver would write it (padding garbage, other fields
/// filled with a constant).
sensor_msgs::PointCloud2 build(const DriverLayout& l)
{
  const std::vector<test::SyntheticPoint> pts = pointsFor(l);
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
    const test::SyntheticPoint& p = pts[i];
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
      test::writeScalar(rec + f.offset, scalar(f.datatype), v);
    }
  }
  return msg;
}

const Field& fieldOf(const DriverLayout& l, const char* name)
{
  for (const Field& f : l.fields)
    if (std::string(f.name) == name)
      return f;
  throw std::runtime_error(std::string("layout has no field ") + name);
}

bool contains(const std::string& s, const std::string& part) { return s.find(part) != std::string::npos; }

}  // namespace

TEST(DriverLayouts, RingTimeAndUnitFoundWithDefaultParameters)
{
  for (const DriverLayout& l : allLayouts())
  {
    SCOPED_TRACE(l.driver);
    const sensor_msgs::PointCloud2 msg = build(l);
    PointCloudView v;
    const Status s = makeView(msg, Params(), v);
    ASSERT_TRUE(s.ok) << s.message;
    EXPECT_EQ(fieldOf(l, l.ring).offset, v.ring.offset);
    EXPECT_EQ(scalar(fieldOf(l, l.ring).datatype), v.ring.type);
    EXPECT_EQ(fieldOf(l, l.time).offset, v.time.offset);
    EXPECT_EQ(scalar(fieldOf(l, l.time).datatype), v.time.type);
    EXPECT_EQ(l.time_scale, v.time_scale);
    EXPECT_EQ(l.point_step, v.point_step);
    EXPECT_EQ(msg.height, v.height);
  }
}

// What the LOAM outputs compute, (t - t of the frame's first point) * time_scale, must be the
// point's time in the sweep for every encoding: float32 relative seconds, integer nanoseconds,
// float64 absolute seconds (~1.7e9: read as float32 it would be quantized to 128 s) and float64
// absolute nanoseconds.
TEST(DriverLayouts, TimesReadThroughTheViewAreSecondsInTheSweep)
{
  for (const DriverLayout& l : allLayouts())
  {
    SCOPED_TRACE(l.driver);
    const sensor_msgs::PointCloud2 msg = build(l);
    const std::vector<test::SyntheticPoint> pts = pointsFor(l);
    PointCloudView v;
    ASSERT_TRUE(makeView(msg, Params(), v).ok);
    ASSERT_TRUE(v.time.present());
    auto seconds = [&](std::size_t i) { return readScalar(v.record(i) + v.time.offset, v.time.type) * v.time_scale; };
    const double t0 = seconds(0);
    double worst = 0;
    for (std::size_t i = 0; i < v.size(); ++i)
      worst = std::max(worst, std::fabs((seconds(i) - t0) - (pts[i].time - pts[0].time)));
    // float64 seconds near 1.7e9 are exact to 0.24 us; the sweep's samples are 111 us apart.
    EXPECT_LT(worst, 0.5e-6) << "largest error of a point's time in the sweep [s]";
    EXPECT_GT(seconds(v.size() - 1) - t0, 0.09) << "the sweep spans 0.1 s";
    if (l.time_kind == TimeKind::AbsoluteSeconds || l.time_kind == TimeKind::AbsoluteNanoseconds)
    {
      EXPECT_NEAR(kStamp, t0, 1e-6) << "absolute times are seconds since the epoch";
    }
  }
}

TEST(DriverLayouts, EveryLayoutIsLabelledAndUnorganizedOnesAlike)
{
  std::vector<std::uint8_t> reference;
  for (const DriverLayout& l : allLayouts())
  {
    SCOPED_TRACE(l.driver);
    const sensor_msgs::PointCloud2 msg = build(l);
    FrameProcessor proc;
    Outputs out;
    const Status s = proc.process(msg, out);
    ASSERT_TRUE(s.ok) << s.message;
    const auto& counts = proc.summary().label_counts;
    EXPECT_EQ(static_cast<std::size_t>(msg.width) * msg.height, proc.summary().points);
    EXPECT_GT(counts[static_cast<int>(Label::Plane)], proc.summary().points / 2) << "the room is mostly walls";
    EXPECT_GT(counts[static_cast<int>(Label::Edge)] + counts[static_cast<int>(Label::Corner)], 0u)
        << "the room's corners and pillar";
    EXPECT_GT(proc.summary().primitives, 0u);
    ASSERT_TRUE(out.labelled);
    EXPECT_EQ(msg.width, out.labelled->width);
    EXPECT_EQ(msg.height, out.labelled->height);
    if (l.organized)
      continue;
    // Same points in the same order: the field layout must not change a single label.
    if (reference.empty())
      reference = proc.result().label;
    else
      EXPECT_EQ(reference, proc.result().label);
  }
}

// Livox's float64 nanoseconds look like seconds to the type alone: "auto" reads the magnitude,
// and an explicit unit overrides it.
TEST(DriverLayouts, TimeUnitOverridesAuto)
{
  const sensor_msgs::PointCloud2 livox = build(livox2());
  PointCloudView v;
  Params p;
  p.time_unit = TimeUnit::S;
  ASSERT_TRUE(makeView(livox, p, v).ok);
  EXPECT_EQ(1.0, v.time_scale);
  p.time_unit = TimeUnit::Ns;
  ASSERT_TRUE(makeView(livox, p, v).ok);
  EXPECT_EQ(1e-9, v.time_scale);

  // An integer time is nanoseconds to "auto"; a driver counting microseconds sets "us".
  const sensor_msgs::PointCloud2 msg = build(ouster());
  const std::vector<std::pair<TimeUnit, double>> units = {
      {TimeUnit::Auto, 1e-9}, {TimeUnit::S, 1.0}, {TimeUnit::Ms, 1e-3}, {TimeUnit::Us, 1e-6}, {TimeUnit::Ns, 1e-9}};
  for (const auto& [unit, scale] : units)
  {
    p.time_unit = unit;
    ASSERT_TRUE(makeView(msg, p, v).ok);
    EXPECT_EQ(scale, v.time_scale) << toString(unit);
  }
}

TEST(DriverLayouts, CustomFieldNames)
{
  DriverLayout l = velodyne();
  l.fields[4].name = "beam";
  l.fields[5].name = "stamp_ns";
  l.fields[5].datatype = PF::UINT32;
  l.ring = "beam";
  l.time = "stamp_ns";
  l.time_kind = TimeKind::RelativeNanoseconds;
  const sensor_msgs::PointCloud2 msg = build(l);

  PointCloudView v;
  Status s = makeView(msg, Params(), v);
  ASSERT_FALSE(s.ok) << "no default name matches 'beam'";

  Params p;
  p.ring_field = "beam";
  p.time_field = " stamp_ns , t ";  // blanks around names are ignored
  ASSERT_TRUE(p.validate().ok);
  s = makeView(msg, p, v);
  ASSERT_TRUE(s.ok) << s.message;
  EXPECT_EQ(16, v.ring.offset);
  EXPECT_EQ(18, v.time.offset);
  EXPECT_EQ(ScalarType::UInt32, v.time.type);
  EXPECT_EQ(1e-9, v.time_scale);

  // A time field not in the list is simply absent (the time is optional).
  p.time_field = "time";
  ASSERT_TRUE(makeView(msg, p, v).ok);
  EXPECT_FALSE(v.time.present());

  FrameProcessor proc(p);
  Outputs out;
  s = proc.process(msg, out);
  EXPECT_TRUE(s.ok) << s.message;
}

// The list's order decides, not the message's: with both `channel` and `ring`, ring_field's first
// name present wins.
TEST(DriverLayouts, FirstNameOfTheParameterWins)
{
  DriverLayout l = velodyne();
  l.point_step = 24;
  l.fields.insert(l.fields.begin(), Field{"channel", 22, PF::UINT16});  // listed first in the message
  sensor_msgs::PointCloud2 msg = build(l);  // channel holds the constant 7, ring the real rings
  PointCloudView v;
  ASSERT_TRUE(makeView(msg, Params(), v).ok);
  EXPECT_EQ(16, v.ring.offset) << "default ring_field lists ring before channel";
  Params p;
  p.ring_field = "channel,ring";
  ASSERT_TRUE(makeView(msg, p, v).ok);
  EXPECT_EQ(22, v.ring.offset);
}

TEST(DriverLayoutErrors, NoRingFieldListsTheNamesTriedAndTheParameter)
{
  DriverLayout l = velodyne();
  l.fields[4].name = "beam";
  const sensor_msgs::PointCloud2 msg = build(l);
  PointCloudView v;
  const Status s = makeView(msg, Params(), v);
  ASSERT_FALSE(s.ok);
  for (const char* part : {"'ring'", "'channel'", "'line'", "'laser_id'", "ring_field", "beam:uint16",
                           "ring_from_elevation"})
    EXPECT_TRUE(contains(s.message, part)) << "missing " << part << " in: " << s.message;

  Params p;
  p.ring_field = "beam_id,laser";
  const Status t = makeView(msg, p, v);
  EXPECT_TRUE(contains(t.message, "'beam_id', 'laser'")) << t.message;
}

TEST(DriverLayoutErrors, WrongTypedRingNamesFieldTypeAndParameter)
{
  DriverLayout l = nebula();
  l.fields[5].datatype = PF::FLOAT32;  // a float `channel`
  l.fields[6].offset = 18;             // azimuth moved so the 4-byte channel fits
  l.fields[7].offset = 22;
  l.fields[8].offset = 26;
  l.fields[9].offset = 30;
  l.point_step = 34;
  const sensor_msgs::PointCloud2 msg = build(l);
  PointCloudView v;
  const Status s = makeView(msg, Params(), v);
  ASSERT_FALSE(s.ok);
  for (const char* part : {"'channel'", "float32", "ring_field", "integer"})
    EXPECT_TRUE(contains(s.message, part)) << "missing " << part << " in: " << s.message;

  // The field named first is what the user asked for: a wrong type is not skipped for the next name.
  DriverLayout both = velodyne();
  both.fields[4] = {"ring", 16, PF::INT16};
  both.point_step = 28;
  both.fields.push_back({"ring_f", 22, PF::FLOAT32});
  const sensor_msgs::PointCloud2 m2 = build(both);
  Params p;
  p.ring_field = "ring_f,ring";
  const Status s2 = makeView(m2, p, v);
  EXPECT_FALSE(s2.ok);
  EXPECT_TRUE(contains(s2.message, "'ring_f'")) << s2.message;
}

TEST(DriverLayoutErrors, RingOrTimeWithSeveralValuesPerPoint)
{
  sensor_msgs::PointCloud2 msg = build(ouster());
  for (auto& f : msg.fields)
    if (f.name == "reflectivity")
      f.count = 2;  // reflectivity + ring as one 2-element field
  for (auto it = msg.fields.begin(); it != msg.fields.end(); ++it)
    if (it->name == "ring")
    {
      msg.fields.erase(it);
      break;
    }
  for (auto& f : msg.fields)
    if (f.name == "reflectivity")
      f.name = "ring";
  PointCloudView v;
  const Status s = makeView(msg, Params(), v);
  ASSERT_FALSE(s.ok);
  EXPECT_TRUE(contains(s.message, "count 2")) << s.message;
  EXPECT_TRUE(contains(s.message, "ring_field")) << s.message;
}

TEST(DriverLayoutParams, FieldListsAndUnitAreCheckedByName)
{
  Params p;
  Status s = applyParamStrings({{"ring_field", "beam, ring"}, {"time_field", "stamp"}, {"time_unit", "us"}}, p);
  ASSERT_TRUE(s.ok) << s.message;
  EXPECT_EQ("beam, ring", p.ring_field);
  EXPECT_EQ("stamp", p.time_field);
  EXPECT_EQ(TimeUnit::Us, p.time_unit);

  // (A failed apply may leave `p` half-written: each case starts from the defaults.)
  Params a;
  s = applyParamStrings({{"time_unit", "sec"}}, a);
  EXPECT_FALSE(s.ok);
  EXPECT_TRUE(contains(s.message, "time_unit") && contains(s.message, "auto, s, ms, us, ns")) << s.message;
  Params b;
  s = applyParamStrings({{"ring_field", "ring,,line"}}, b);
  EXPECT_FALSE(s.ok);
  EXPECT_TRUE(contains(s.message, "ring_field")) << s.message;
  Params c;
  s = applyParamStrings({{"time_field", " "}}, c);
  EXPECT_FALSE(s.ok);
  EXPECT_TRUE(contains(s.message, "time_field")) << s.message;

  // Start-up only: dynamic_reconfigure leaves them as loaded.
  Params q;
  q.ring_field = "beam";
  q.time_unit = TimeUnit::Ms;
  const Params r = fromConfig(toConfig(q), q);
  EXPECT_EQ("beam", r.ring_field);
  EXPECT_EQ(TimeUnit::Ms, r.time_unit);
}
