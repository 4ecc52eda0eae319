// RingCurvatureNodelet's LOAM outputs inside a nodelet::Loader in this test process (a nodelet
// manager), fed by a publisher in the same process: A-LOAM's point layout sorted by ring with the
// sweep times, the feature sets and their report on ~frame_stats, and the clouds deskewed with
// the odometry of the LiDAR or of a base whose mounting tf gives.
#include <gtest/gtest.h>
#include <nav_msgs/Odometry.h>
#include <ros/ros.h>
#include <tf2_ros/static_transform_broadcaster.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <mutex>
#include <set>
#include <string>
#include <vector>

#include "ring_curvature/ros/ring_curvature_nodelet.hpp"
#include "keep_messages.hpp"
#include "nodelet_harness.hpp"

using namespace ring_curvature_test;
using sensor_msgs::PointCloud2;

namespace
{

// Two nodelets on one input, NAME deskewing with the odometry on ODOM (its other parameters set
// by the caller before) and NAME_plain not: the last ~loam/cloud of each, the first one's last
// ~frame_stats. (Both nodelets live in this process: roscpp counts them as one subscriber.)
struct DeskewPair
{
  DeskewPair(Manager& m, const std::string& name, const std::string& input, const std::string& odom_topic)
  {
    ros::NodeHandle nh;
    nh.setParam(name + "/deskew_odometry", odom_topic);
    loaded = m.load(name, input) && m.load(name + "_plain", input);
    pub = nh.advertise<PointCloud2>(input, 2);
    odom = nh.advertise<nav_msgs::Odometry>(odom_topic, 10, true);
    for (int i = 0; i < 2; ++i)
      subs.push_back(nh.subscribe<PointCloud2>(name + (i == 0 ? "" : "_plain") + "/loam/cloud", 10,
                                               [this, i](const PointCloud2::ConstPtr& c) {
                                                 std::lock_guard<std::mutex> l(mutex);
                                                 got[i] = c;
                                               }));
    subs.push_back(nh.subscribe<ring_curvature::FrameStats>(name + "/frame_stats", 10,
                                                            [this](const ring_curvature::FrameStats::ConstPtr& st) {
                                                              std::lock_guard<std::mutex> l(mutex);
                                                              stats = st;
                                                            }));
  }
  bool connected() const
  {
    return waitUntil([&] { return pub.getNumSubscribers() > 0 && odom.getNumSubscribers() > 0; });
  }
  // Poses of `child` 0.2 and 0.1 s before `stamp`, driving along its x at 6 m/s.
  void drive(const ros::Time& stamp, const std::string& child = "")
  {
    for (int k = 2; k >= 1; --k)
    {
      nav_msgs::Odometry o;
      o.header.stamp = stamp - ros::Duration(0.1 * k);
      o.child_frame_id = child;
      o.pose.pose.orientation.w = 1.0;
      o.pose.pose.position.x = 6.0 * (o.header.stamp - stamp).toSec();
      odom.publish(o);
      ros::WallDuration(0.05).sleep();
    }
  }
  // Publishes the first fixture frame stamped `t`; true once both clouds and the stats are in.
  bool publishAndWait(const ros::Time& t)
  {
    {
      std::lock_guard<std::mutex> l(mutex);
      got[0] = got[1] = nullptr;
      stats = nullptr;
    }
    auto in = copyOf(*frames()[0]);
    in->header.stamp = t;
    pub.publish(in);
    return waitUntil([&] {
      std::lock_guard<std::mutex> l(mutex);
      return got[0] && got[1] && stats;
    });
  }
  // Each point of the deskewed cloud less the plain one's, with its sweep time.
  template <class F>
  void eachDifference(F f) const
  {
    ASSERT_EQ(got[0]->width, got[1]->width);
    for (std::uint32_t k = 0; k < got[0]->width; ++k)
    {
      float a[5], b[5];
      std::memcpy(a, &got[0]->data[k * 32u], 20);
      std::memcpy(b, &got[1]->data[k * 32u], 20);
      ASSERT_EQ(a[4], b[4]) << "same point, same ring and time, at " << k;
      f(k, a[0] - b[0], a[1] - b[1], a[2] - b[2], a[4] - std::floor(a[4]));
    }
  }
  // Every point moved along x by the distance driven (6 m/s) from the reference time `ref` into
  // the sweep to its firing, sideways and up not at all; early and late points both present.
  void expectForwardShift(float ref) const
  {
    std::size_t early = 0, late = 0;
    eachDifference([&](std::uint32_t k, float dx, float dy, float dz, float t) {
      EXPECT_NEAR(dx, 6.0f * (t - ref), 2e-3f) << "at " << k;
      EXPECT_NEAR(dy, 0.0f, 1e-3f);
      EXPECT_NEAR(dz, 0.0f, 1e-3f);
      early += t < 0.01f ? 1 : 0;
      late += t > 0.09f ? 1 : 0;
    });
    EXPECT_GT(early, 100u);
    EXPECT_GT(late, 100u);
  }
  bool loaded = false;
  ros::Publisher pub, odom;
  std::vector<ros::Subscriber> subs;
  mutable std::mutex mutex;
  PointCloud2::ConstPtr got[2];
  ring_curvature::FrameStats::ConstPtr stats;
};

}  // namespace

// The LOAM outputs: A-LOAM's point layout, sorted by ring, intensity = ring + sweep time, the
// sharp set inside the less sharp one and the flat inside the less flat, counts and the
// degeneracy report on ~frame_stats.
TEST(NodeletInProcess, LoamOutputsSortedByRingWithSweepTimes)
{
  Manager m;
  auto rc = m.load("/rc_loam", "/input_loam");
  ASSERT_TRUE(rc);
  ros::NodeHandle nh;
  ros::Publisher pub = nh.advertise<PointCloud2>("/input_loam", 1);
  const char* names[5] = {"cloud", "sharp", "less_sharp", "flat", "less_flat"};
  std::mutex mutex;
  std::vector<PointCloud2::ConstPtr> got[5];
  std::vector<ring_curvature::FrameStats::ConstPtr> stats;
  std::vector<ros::Subscriber> subs;
  for (int i = 0; i < 5; ++i)
    subs.push_back(keepMessages<PointCloud2>(nh, std::string("/rc_loam/loam/") + names[i], mutex, got[i]));
  subs.push_back(keepMessages<ring_curvature::FrameStats>(nh, "/rc_loam/frame_stats", mutex, stats));
  ASSERT_TRUE(waitUntil([&] { return pub.getNumSubscribers() > 0; }));
  pub.publish(copyOf(*frames()[0]));
  ASSERT_TRUE(waitUntil([&] {
    std::lock_guard<std::mutex> l(mutex);
    for (const auto& g : got)
      if (g.empty()) return false;
    return !stats.empty();
  }));
  std::lock_guard<std::mutex> l(mutex);
  const std::size_t input_points = static_cast<std::size_t>(frames()[0]->width) * frames()[0]->height;
  std::vector<std::set<std::array<float, 4>>> sets(5);
  for (int i = 0; i < 5; ++i)
  {
    const PointCloud2& c = *got[i].back();
    SCOPED_TRACE(names[i]);
    EXPECT_EQ(c.header.stamp, frames()[0]->header.stamp);
    ASSERT_EQ(4u, c.fields.size());
    EXPECT_EQ("x", c.fields[0].name);
    EXPECT_EQ(0u, c.fields[0].offset);
    EXPECT_EQ("intensity", c.fields[3].name);
    EXPECT_EQ(16u, c.fields[3].offset);
    ASSERT_EQ(32u, c.point_step);
    ASSERT_EQ(c.data.size(), static_cast<std::size_t>(c.width) * 32u);
    EXPECT_GT(c.width, 0u);
    EXPECT_LE(c.width, input_points);
    int last_ring = -1;
    float latest = 0.0f;
    for (std::uint32_t k = 0; k < c.width; ++k)
    {
      float rec[5];
      std::memcpy(rec, &c.data[k * 32u], 12);
      std::memcpy(&rec[3], &c.data[k * 32u + 16u], 4);
      const int ring = static_cast<int>(std::floor(rec[3]));
      const float t = rec[3] - static_cast<float>(ring);
      ASSERT_GE(ring, last_ring) << "not sorted by ring at point " << k;
      ASSERT_LT(ring, 16);
      ASSERT_GE(t, 0.0f);
      ASSERT_LE(t, 0.1f + 1e-5f);  // scan_period
      latest = std::max(latest, t);
      last_ring = ring;
      sets[static_cast<std::size_t>(i)].insert({rec[0], rec[1], rec[2], rec[3]});
    }
    if (i == 0)
    {
      EXPECT_GT(latest, 0.09f) << "a whole sweep spans the scan period";
    }
  }
  for (const auto& p : sets[1]) EXPECT_EQ(1u, sets[2].count(p)) << "sharp point not in less sharp";
  for (const auto& p : sets[3]) EXPECT_EQ(1u, sets[4].count(p)) << "flat point not in less flat";
  for (const auto& p : sets[4]) EXPECT_EQ(0u, sets[2].count(p)) << "a point both less flat and less sharp";
  const auto& st = *stats.back();
  EXPECT_TRUE(st.loam);
  EXPECT_EQ(st.sharp, got[1].back()->width);
  EXPECT_EQ(st.less_sharp, got[2].back()->width);
  EXPECT_EQ(st.flat, got[3].back()->width);
  EXPECT_EQ(st.less_flat, got[4].back()->width);
  EXPECT_GT(st.plane_constraints, 0u);
  for (std::size_t k = 1; k < 6; ++k) EXPECT_LE(st.degeneracy_eigenvalues[k - 1], st.degeneracy_eigenvalues[k]);
  double norm = 0;
  for (const double v : st.weakest_direction) norm += v * v;
  EXPECT_NEAR(1.0, norm, 1e-6);
}

// Deskew (~deskew_odometry) to the stamp (~deskew_reference: stamp): with two recent poses the
// LOAM clouds move each point by the motion up to its firing time (the sweep's start is the stamp
// here) and keep the stamp; a frame far from the last pose is left as it is and says so on
// ~frame_stats.
TEST(NodeletInProcess, LoamCloudsDeskewedWithRecentOdometry)
{
  Manager m;
  ros::param::set("/rc_deskew/deskew_reference", "stamp");
  DeskewPair d(m, "/rc_deskew", "/input_deskew", "/odom_deskew");
  ASSERT_TRUE(d.loaded && d.connected());
  const ros::Time stamp = frames()[0]->header.stamp;
  d.drive(stamp);
  ASSERT_TRUE(d.publishAndWait(stamp));
  {
    std::lock_guard<std::mutex> l(d.mutex);
    EXPECT_TRUE(d.stats->deskewed);
    d.expectForwardShift(0.0f);  // to the sweep's start
  }
  // ten seconds after the last pose: no motion model, the points as they are
  ASSERT_TRUE(d.publishAndWait(stamp + ros::Duration(10.0)));
  std::lock_guard<std::mutex> l(d.mutex);
  EXPECT_FALSE(d.stats->deskewed);
  ASSERT_EQ(d.got[0]->width, d.got[1]->width);
  EXPECT_EQ(0, std::memcmp(d.got[0]->data.data(), d.got[1]->data.data(), d.got[0]->data.size()));
  EXPECT_EQ(d.got[0]->header.stamp, stamp + ros::Duration(10.0));
}

// Deskew to the sweep's middle (the default): each point moves by the motion between its firing
// and the middle of the sweep, and the clouds carry that time; a frame that cannot be deskewed
// carries it too (its points lie about the middle of the sweep on average), so that the first
// frames, sent before any pose exists, agree with the later ones.
TEST(NodeletInProcess, LoamCloudsDeskewedToTheSweepsMiddleAndStampedSo)
{
  Manager m;
  DeskewPair d(m, "/rc_middle", "/input_middle", "/odom_middle");
  ASSERT_TRUE(d.loaded && d.connected());
  const ros::Time stamp = frames()[0]->header.stamp;
  const ros::Duration half(0.05);  // scan_period 0.1 s; the sweep starts at the stamp here
  d.drive(stamp);
  ASSERT_TRUE(d.publishAndWait(stamp));
  {
    std::lock_guard<std::mutex> l(d.mutex);
    EXPECT_TRUE(d.stats->deskewed);
    // (to a microsecond: the sweep's start is the first time field value, a float)
    EXPECT_NEAR((d.got[0]->header.stamp - (stamp + half)).toSec(), 0.0, 1e-6);
    EXPECT_EQ(d.got[1]->header.stamp, stamp) << "the plain nodelet's clouds keep the input's stamp";
    d.expectForwardShift(0.05f);  // points fired before the middle move back, those after it ahead
  }
  ASSERT_TRUE(d.publishAndWait(stamp + ros::Duration(10.0)));
  std::lock_guard<std::mutex> l(d.mutex);
  EXPECT_FALSE(d.stats->deskewed);
  EXPECT_EQ(d.got[0]->data, d.got[1]->data);
  EXPECT_NEAR((d.got[0]->header.stamp - (stamp + ros::Duration(10.0) + half)).toSec(), 0.0, 1e-6);
}

// Deskew with the odometry of a base (~deskew_use_tf): no deskew until tf has the LiDAR's
// mounting, then the base's forward motion moves the points along the LiDAR's own axis (-y: it is
// mounted turned by 90 degrees).
TEST(NodeletInProcess, LoamCloudsDeskewedWithBaseOdometryThroughTf)
{
  Manager m;
  ros::param::set("/rc_base/deskew_use_tf", true);
  ros::param::set("/rc_base/deskew_reference", "stamp");
  DeskewPair d(m, "/rc_base", "/input_base", "/odom_base");
  ASSERT_TRUE(d.loaded && d.connected());
  const ros::Time stamp = frames()[0]->header.stamp;
  d.drive(stamp, "/base_link");  // (tf2 refuses a leading slash: the mounting must drop it)
  ASSERT_TRUE(d.publishAndWait(stamp));
  {
    std::lock_guard<std::mutex> l(d.mutex);
    EXPECT_FALSE(d.stats->deskewed) << "deskewed without the mounting";
    EXPECT_EQ(d.got[0]->data, d.got[1]->data);
  }
  tf2_ros::StaticTransformBroadcaster broadcaster;
  geometry_msgs::TransformStamped mount;
  mount.header.frame_id = "base_link";
  mount.child_frame_id = frames()[0]->header.frame_id;
  mount.transform.translation.x = 1.2;
  mount.transform.translation.z = 1.8;
  mount.transform.rotation.z = std::sin(M_PI / 4);
  mount.transform.rotation.w = std::cos(M_PI / 4);
  broadcaster.sendTransform(mount);
  ASSERT_TRUE(waitUntil([&] {
    if (!d.publishAndWait(stamp)) return false;
    std::lock_guard<std::mutex> l(d.mutex);
    return static_cast<bool>(d.stats->deskewed);
  })) << "the mounting never taken from tf";
  std::lock_guard<std::mutex> l(d.mutex);
  d.eachDifference([](std::uint32_t k, float dx, float dy, float dz, float t) {
    EXPECT_NEAR(dx, 0.0f, 1e-3f) << "at " << k;
    EXPECT_NEAR(dy, -6.0f * t, 2e-3f) << "at " << k;
    EXPECT_NEAR(dz, 0.0f, 1e-3f) << "at " << k;
  });
}

int main(int argc, char** argv) { return runTests(argc, argv, "test_nodelet_inprocess_loam"); }
