// Deskewing the LOAM clouds: the odometry's motion model (OdometryMotion) and the points moved to
// the sensor's pose at the cloud's stamp (FrameProcessor), whatever time convention the driver has.
#include <gtest/gtest.h>

#include <sensor_msgs/PointField.h>

#include <cmath>
#include <cstring>
#include <limits>

#include "ring_curvature/ros/frame_processor.hpp"
#include "ring_curvature/ros/odometry_motion.hpp"

using ring_curvature::FrameProcessor;
using ring_curvature::OdometryMotion;
using ring_curvature::Outputs;
using ring_curvature::OutputSelection;
using ring_curvature::SweepMotion;

namespace
{
constexpr double kPeriod = 0.1;

// A pose of a sensor driving at `speed` m/s along x while turning at `yaw_rate` rad/s, at time t.
nav_msgs::Odometry poseAt(double t, double speed, double yaw_rate)
{
  nav_msgs::Odometry o;
  o.header.stamp = ros::Time(100.0 + t);
  const double yaw = yaw_rate * t;
  o.pose.pose.orientation.z = std::sin(yaw / 2);
  o.pose.pose.orientation.w = std::cos(yaw / 2);
  // on the circle of that turn (a straight line without one)
  o.pose.pose.position.x = yaw_rate != 0 ? speed / yaw_rate * std::sin(yaw) : speed * t;
  o.pose.pose.position.y = yaw_rate != 0 ? speed / yaw_rate * (1 - std::cos(yaw)) : 0.0;
  return o;
}

// 16 rings x 900 samples on a cylinder of radius 10 m; `time` in seconds, from t0 to t0 + 0.1.
sensor_msgs::PointCloud2 cylinder(double t0)
{
  sensor_msgs::PointCloud2 c;
  c.header.stamp = ros::Time(100.0);
  c.header.frame_id = "lidar";
  const char* names[5] = {"x", "y", "z", "time", "ring"};
  const std::uint8_t types[5] = {7, 7, 7, 7, 4};  // float32 x 4, uint16
  for (std::uint32_t i = 0; i < 5; ++i)
  {
    sensor_msgs::PointField f;
    f.name = names[i];
    f.offset = 4 * i;
    f.datatype = types[i];
    f.count = 1;
    c.fields.push_back(f);
  }
  const std::uint32_t width = 900, rings = 16;
  c.point_step = 18;
  c.height = 1;
  c.width = width * rings;
  c.row_step = c.point_step * c.width;
  c.data.resize(c.row_step);
  std::size_t k = 0;
  for (std::uint32_t j = 0; j < width; ++j)
    for (std::uint16_t r = 0; r < rings; ++r, ++k)
    {
      const double az = -2 * M_PI * j / width, el = (-15.0 + 2.0 * r) * M_PI / 180;  // clockwise
      const float rec[4] = {static_cast<float>(10 * std::cos(az)), static_cast<float>(10 * std::sin(az)),
                            static_cast<float>(10 * std::tan(el)), static_cast<float>(t0 + kPeriod * j / width)};
      std::memcpy(&c.data[k * 18], rec, 16);
      std::memcpy(&c.data[k * 18 + 16], &r, 2);
    }
  return c;
}

// x, y, z and the sweep time (intensity's fraction) of every point of a LOAM cloud.
std::vector<std::array<float, 4>> points(const sensor_msgs::PointCloud2& c)
{
  std::vector<std::array<float, 4>> out(c.width);
  for (std::uint32_t k = 0; k < c.width; ++k)
  {
    std::memcpy(out[k].data(), &c.data[k * c.point_step], 12);
    float i;
    std::memcpy(&i, &c.data[k * c.point_step + 16], 4);
    out[k][3] = i - std::floor(i);
  }
  return out;
}
}  // namespace

TEST(OdometryMotion, NeedsTwoRecentPoses)
{
  OdometryMotion m;
  SweepMotion s;
  EXPECT_FALSE(m.motionFor(ros::Time(100.0), kPeriod, 0.5, 0.5, s));
  m.add(poseAt(0.0, 6.0, 0.0));
  EXPECT_FALSE(m.motionFor(ros::Time(100.1), kPeriod, 0.5, 0.5, s)) << "one pose is no motion";
  m.add(poseAt(0.1, 6.0, 0.0));
  ASSERT_TRUE(m.motionFor(ros::Time(100.2), kPeriod, 0.5, 0.5, s));
  EXPECT_NEAR(0.6, s.translation[0], 1e-9);
  EXPECT_FALSE(m.motionFor(ros::Time(101.0), kPeriod, 0.5, 0.5, s)) << "0.9 s after the last pose: stale";
}

TEST(OdometryMotion, MeanBodyFrameMotionOverTheWindow)
{
  OdometryMotion m;
  for (int k = 0; k <= 10; ++k) m.add(poseAt(0.1 * k, 6.0, 0.5));  // a turn: 0.05 rad per sweep
  SweepMotion s;
  ASSERT_TRUE(m.motionFor(ros::Time(101.1), kPeriod, 0.5, 0.5, s));
  EXPECT_NEAR(0.0, s.rotation[0], 1e-9);
  EXPECT_NEAR(0.05, s.rotation[2], 1e-9);
  // the chord of the last 0.5 s (0.25 rad) of the turn, seen from its start, per sweep: forward
  // and a little left
  const double R = 6.0 / 0.5, chord = 2 * R * std::sin(0.125);
  EXPECT_NEAR(chord * std::cos(0.125) / 5, s.translation[0], 1e-9);
  EXPECT_NEAR(chord * std::sin(0.125) / 5, s.translation[1], 1e-9);
  // a window of one step: the last step alone
  ASSERT_TRUE(m.motionFor(ros::Time(101.1), kPeriod, 0.1, 0.5, s));
  EXPECT_NEAR(2 * R * std::sin(0.025) * std::cos(0.025), s.translation[0], 1e-9);
}

TEST(OdometryMotion, TimeGoingBackStartsAgainAndBadPosesAreIgnored)
{
  OdometryMotion m;
  m.add(poseAt(0.0, 6.0, 0.0));
  m.add(poseAt(0.1, 6.0, 0.0));
  m.add(poseAt(0.0, 2.0, 0.0));  // the bag played again
  SweepMotion s;
  EXPECT_FALSE(m.motionFor(ros::Time(100.1), kPeriod, 0.5, 0.5, s));
  nav_msgs::Odometry bad = poseAt(0.1, 2.0, 0.0);
  bad.pose.pose.orientation.w = std::nan("");
  m.add(bad);
  EXPECT_FALSE(m.motionFor(ros::Time(100.1), kPeriod, 0.5, 0.5, s));
  m.add(poseAt(0.1, 2.0, 0.0));
  ASSERT_TRUE(m.motionFor(ros::Time(100.2), kPeriod, 0.5, 0.5, s));
  EXPECT_NEAR(0.2, s.translation[0], 1e-9);
}

// An odometry of the frame the LiDAR is mounted on (a base): the LiDAR's own motion is the base's
// seen from the mounting, the same as an odometry of the LiDAR itself would give.
TEST(OdometryMotion, BaseMotionMovedToTheLidarByItsMounting)
{
  Eigen::Isometry3d mount = Eigen::Isometry3d::Identity();  // the LiDAR in the base frame
  mount.linear() = Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  mount.translation() = Eigen::Vector3d(1.2, 0.3, 1.8);
  OdometryMotion base, lidar;
  for (int k = 0; k <= 10; ++k)
  {
    nav_msgs::Odometry o = poseAt(0.1 * k, 6.0, 0.5);
    o.child_frame_id = "/base_link";
    base.add(o);
    const auto& q = o.pose.pose.orientation;
    const auto& t = o.pose.pose.position;
    Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
    pose.linear() = Eigen::Quaterniond(q.w, q.x, q.y, q.z).toRotationMatrix();
    pose.translation() = Eigen::Vector3d(t.x, t.y, t.z);
    const Eigen::Isometry3d at = pose * mount;
    const Eigen::Quaterniond aq(at.rotation());
    o.pose.pose.orientation.w = aq.w();
    o.pose.pose.orientation.x = aq.x();
    o.pose.pose.orientation.y = aq.y();
    o.pose.pose.orientation.z = aq.z();
    o.pose.pose.position.x = at.translation().x();
    o.pose.pose.position.y = at.translation().y();
    o.pose.pose.position.z = at.translation().z();
    lidar.add(o);
  }
  std::string child;
  base.childFrame(child);
  EXPECT_EQ("/base_link", child);
  SweepMotion from_base, own, unmounted;
  ASSERT_TRUE(base.motionFor(ros::Time(101.1), kPeriod, 0.5, 0.5, from_base, &mount));
  ASSERT_TRUE(lidar.motionFor(ros::Time(101.1), kPeriod, 0.5, 0.5, own));
  ASSERT_TRUE(base.motionFor(ros::Time(101.1), kPeriod, 0.5, 0.5, unmounted));
  for (std::size_t i = 0; i < 3; ++i)
  {
    EXPECT_NEAR(own.rotation[i], from_base.rotation[i], 1e-9) << i;
    EXPECT_NEAR(own.translation[i], from_base.translation[i], 1e-9) << i;
  }
  // turned by 90 degrees, the base's forward motion is the LiDAR's -y (less the 1.5 cm the turn
  // swings the LiDAR's 0.3 m offset back); the turn swings the LiDAR, 1.2 m ahead of the base's
  // origin, 6 cm sideways: its +x
  EXPECT_NEAR(-unmounted.translation[0], from_base.translation[1], 0.03);
  EXPECT_GT(from_base.translation[0] - unmounted.translation[1], 0.05);
  EXPECT_NEAR(unmounted.rotation[2], from_base.rotation[2], 1e-9);
}

// Velodyne's times run up to the stamp (-0.1 .. 0), Ouster's from it (0 .. 0.1): either way the
// points fired at the stamp stay, the others move by the motion between their time and it.
TEST(FrameProcessorDeskew, PointsReferToTheStampWhateverTheTimeConvention)
{
  SweepMotion motion;
  motion.translation = {0.6, 0.0, 0.0};
  OutputSelection select;
  select.labelled = select.primitives = select.edges = select.planes = select.markers = false;
  select.loam_cloud = true;
  for (const double t0 : {-0.1, 0.0})
  {
    SCOPED_TRACE(t0);
    const sensor_msgs::PointCloud2 in = cylinder(t0);
    FrameProcessor plain, moved;
    moved.setSweepMotion(&motion);
    Outputs a, b;
    ASSERT_TRUE(plain.process(in, a, select).ok);
    ASSERT_TRUE(moved.process(in, b, select).ok);
    EXPECT_FALSE(plain.summary().deskewed);
    EXPECT_TRUE(moved.summary().deskewed);
    const auto pa = points(*a.loam_cloud), pb = points(*b.loam_cloud);
    ASSERT_EQ(pa.size(), pb.size());
    ASSERT_GT(pa.size(), 10000u);
    for (std::size_t k = 0; k < pa.size(); ++k)
    {
      ASSERT_EQ(pa[k][3], pb[k][3]);
      // fired at sweep time t, i.e. t + t0 after the stamp: the sensor had moved 6 m/s that long
      const double expected = 6.0 * (pa[k][3] + t0);
      ASSERT_NEAR(expected, pb[k][0] - pa[k][0], 2e-3) << "point " << k;
      ASSERT_EQ(pa[k][1], pb[k][1]);
      ASSERT_EQ(pa[k][2], pb[k][2]);
    }
  }
}

// A NaN in the time field (a driver's bad record) must not take the deskew out of its table.
TEST(FrameProcessorDeskew, NanTimesAreSurvived)
{
  sensor_msgs::PointCloud2 in = cylinder(0.0);
  const float nan = std::numeric_limits<float>::quiet_NaN();
  for (std::size_t k = 0; k < in.width; k += 97) std::memcpy(&in.data[k * in.point_step + 12], &nan, 4);
  SweepMotion motion;
  motion.rotation = {0.0, 0.0, 0.05};
  motion.translation = {0.6, 0.0, 0.0};
  FrameProcessor fp;
  fp.setSweepMotion(&motion);
  OutputSelection select;
  select.loam_cloud = true;
  Outputs out;
  ASSERT_TRUE(fp.process(in, out, select).ok);
  EXPECT_TRUE(fp.summary().deskewed);
  std::size_t finite = 0;
  for (const auto& p : points(*out.loam_cloud)) finite += std::isfinite(p[0] + p[1] + p[2]) ? 1 : 0;
  EXPECT_EQ(finite, out.loam_cloud->width);
}
