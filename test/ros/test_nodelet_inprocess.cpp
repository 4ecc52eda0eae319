// RingCurvatureNodelet inside a nodelet::Loader in this test process (a nodelet manager), fed by
// a publisher in the same process: outputs per frame, zero copy (the nodelet reads the very
// buffer published and subscribers get the very objects it published), laziness, two
// independent instances, ring datatypes / reordered fields, and a bad frame followed by a good one.
#include <gtest/gtest.h>
#include <nav_msgs/Odometry.h>
#include <nodelet/loader.h>
#include <ros/ros.h>
#include <tf2_ros/static_transform_broadcaster.h>
#include <visualization_msgs/MarkerArray.h>

#include <boost/make_shared.hpp>
#include <array>
#include <cmath>
#include <cstring>
#include <functional>
#include <set>
#include <mutex>

#include "ring_curvature/ros/param_loading.hpp"
#include "ring_curvature/ros/ring_curvature_nodelet.hpp"
#include "cloud_builders.hpp"
#include "output_checks.hpp"

using namespace ring_curvature_test;
using ring_curvature::RingCurvatureNodelet;
using sensor_msgs::PointCloud2;

namespace
{

const double kTimeout = 10.0;  // [s] bound on every wait

bool waitUntil(const std::function<bool()>& cond, double seconds = kTimeout)
{
  const ros::WallTime end = ros::WallTime::now() + ros::WallDuration(seconds);
  while (!cond())
  {
    if (ros::WallTime::now() > end || !ros::ok())
      return false;
    ros::WallDuration(0.005).sleep();
  }
  return true;
}

const std::vector<PointCloud2::ConstPtr>& frames()
{
  static const auto f =
      readClouds(std::string(RC_SOURCE_DIR) + "/rosbag_fixtures/nebula_vlp16_lastreturn_4scans.bag", "/velodyne_points");
  return f;
}

// labelled_points, primitives, edges, planes, markers, frame_stats
constexpr std::size_t kOutputTopics = 6;

// Keeps every message received on the outputs of one nodelet.
struct Collector
{
  explicit Collector(const std::string& ns)
  {
    ros::NodeHandle nh;
    subs.push_back(nh.subscribe<PointCloud2>(ns + "/labelled_points", 10, [this](const PointCloud2::ConstPtr& m) {
      std::lock_guard<std::mutex> l(mutex);
      labelled.push_back(m);
    }));
    subs.push_back(nh.subscribe<ring_curvature::PrimitiveArray>(
        ns + "/primitives", 10, [this](const ring_curvature::PrimitiveArray::ConstPtr& m) {
          std::lock_guard<std::mutex> l(mutex);
          primitives.push_back(m);
        }));
    subs.push_back(nh.subscribe<PointCloud2>(ns + "/edges", 10, [this](const PointCloud2::ConstPtr& m) {
      std::lock_guard<std::mutex> l(mutex);
      edges.push_back(m);
    }));
    subs.push_back(nh.subscribe<PointCloud2>(ns + "/planes", 10, [this](const PointCloud2::ConstPtr& m) {
      std::lock_guard<std::mutex> l(mutex);
      planes.push_back(m);
    }));
    subs.push_back(nh.subscribe<visualization_msgs::MarkerArray>(
        ns + "/markers", 10, [this](const visualization_msgs::MarkerArray::ConstPtr& m) {
          std::lock_guard<std::mutex> l(mutex);
          markers.push_back(m);
        }));
    subs.push_back(nh.subscribe<ring_curvature::FrameStats>(
        ns + "/frame_stats", 10, [this](const ring_curvature::FrameStats::ConstPtr& m) {
          std::lock_guard<std::mutex> l(mutex);
          stats.push_back(m);
        }));
  }
  bool complete(std::size_t n)
  {
    std::lock_guard<std::mutex> l(mutex);
    return labelled.size() >= n && primitives.size() >= n && edges.size() >= n && planes.size() >= n &&
           markers.size() >= n && stats.size() >= n;
  }
  std::size_t total()
  {
    std::lock_guard<std::mutex> l(mutex);
    return labelled.size() + primitives.size() + edges.size() + planes.size() + markers.size() + stats.size();
  }
  std::mutex mutex;
  std::vector<ros::Subscriber> subs;
  std::vector<PointCloud2::ConstPtr> labelled, edges, planes;
  std::vector<ring_curvature::PrimitiveArray::ConstPtr> primitives;
  std::vector<visualization_msgs::MarkerArray::ConstPtr> markers;
  std::vector<ring_curvature::FrameStats::ConstPtr> stats;
};

// A manager whose instances the test can reach (the factory keeps a pointer to each).
class Manager
{
public:
  Manager()
    : loader_([this](const std::string&) {
        auto n = boost::make_shared<RingCurvatureNodelet>();
        last_ = n;
        return n;
      })
  {
  }
  boost::shared_ptr<RingCurvatureNodelet> load(const std::string& name, const std::string& input)
  {
    nodelet::M_string remap{{ros::names::resolve("velodyne_points"), ros::names::resolve(input)}};
    if (!loader_.load(name, "ring_curvature/RingCurvatureNodelet", remap, {}))
      return nullptr;
    return last_;
  }
  bool unload(const std::string& name) { return loader_.unload(name); }

private:
  // Declared before last_ so that the nodelets die inside the loader's destructor, while the
  // callback queues their timers and subscribers use still exist (as in a real manager).
  nodelet::Loader loader_;
  boost::shared_ptr<RingCurvatureNodelet> last_;
};

PointCloud2::Ptr copyOf(const PointCloud2& c) { return boost::make_shared<PointCloud2>(c); }

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
  bool loaded = false;
  ros::Publisher pub, odom;
  std::vector<ros::Subscriber> subs;
  mutable std::mutex mutex;
  PointCloud2::ConstPtr got[2];
  ring_curvature::FrameStats::ConstPtr stats;
};

}  // namespace

TEST(NodeletInProcess, OneOutputPerTopicPerFrameAndZeroCopy)
{
  Manager m;
  auto rc = m.load("/rc_zero", "/input_zero");
  ASSERT_TRUE(rc);
  ros::NodeHandle nh;
  ros::Publisher pub = nh.advertise<PointCloud2>("/input_zero", 1);
  Collector out("/rc_zero");
  ASSERT_TRUE(waitUntil([&] { return pub.getNumSubscribers() > 0; })) << "nodelet never subscribed";

  for (std::size_t k = 0; k < frames().size(); ++k)
  {
    const PointCloud2::Ptr in = copyOf(*frames()[k]);
    pub.publish(in);  // by shared pointer: intra-process, no serialization
    ASSERT_TRUE(waitUntil([&] { return out.complete(k + 1); })) << "frame " << k;
    const auto st = rc->stats();
    // The nodelet read this very message and this very point buffer...
    EXPECT_EQ(static_cast<const void*>(in.get()), st.last_input_msg);
    EXPECT_EQ(static_cast<const void*>(in->data.data()), st.last_input_data);
    // ...and the subscribers got the very objects it published.
    std::lock_guard<std::mutex> l(out.mutex);
    EXPECT_EQ(st.last_labelled, static_cast<const void*>(out.labelled[k].get()));
    EXPECT_EQ(st.last_primitives, static_cast<const void*>(out.primitives[k].get()));
    EXPECT_EQ(st.last_edges, static_cast<const void*>(out.edges[k].get()));
    EXPECT_EQ(st.last_planes, static_cast<const void*>(out.planes[k].get()));
    checkLabelled(*in, *out.labelled[k]);
    checkPrimitives(*out.labelled[k], *out.primitives[k]);
    checkSubset(*in, *out.labelled[k], *out.edges[k], 2, 3, "edges");
    checkSubset(*in, *out.labelled[k], *out.planes[k], 1, 1, "planes");
    expectSameHeader(in->header, out.markers[k]->markers.empty() ? in->header : out.markers[k]->markers[0].header,
                     "markers");
    // the per-frame stats describe this very frame
    const ring_curvature::FrameStats& fs = *out.stats[k];
    expectSameHeader(in->header, fs.header, "frame_stats");
    EXPECT_EQ(in->width * in->height, fs.points);
    std::uint32_t labelled_total = 0;
    for (std::uint32_t c : fs.label_counts) labelled_total += c;
    EXPECT_EQ(fs.points, labelled_total);
    EXPECT_EQ(out.primitives[k]->primitives.size(), fs.primitives);
    const float core = fs.grid_ms + fs.features_ms + fs.thresholds_ms + fs.classification_ms + fs.primitives_ms +
                       fs.core_output_ms;
    EXPECT_GT(core, 0.0f);
    EXPECT_GE(fs.callback_ms, core + fs.messages_ms);  // the callback contains every stage
  }
  ros::WallDuration(0.3).sleep();  // nothing extra may trail in
  std::lock_guard<std::mutex> l(out.mutex);
  EXPECT_EQ(frames().size(), out.labelled.size());
  EXPECT_EQ(frames().size(), out.primitives.size());
  EXPECT_EQ(frames().size(), out.edges.size());
  EXPECT_EQ(frames().size(), out.planes.size());
  EXPECT_EQ(frames().size(), out.markers.size());
  EXPECT_EQ(frames().size(), out.stats.size());
}

TEST(NodeletInProcess, LazyNoSubscriptionWithoutOutputSubscribers)
{
  Manager m;
  auto rc = m.load("/rc_lazy", "/input_lazy");
  ASSERT_TRUE(rc);
  ros::NodeHandle nh;
  ros::Publisher pub = nh.advertise<PointCloud2>("/input_lazy", 1);
  ros::WallDuration(0.5).sleep();
  EXPECT_EQ(0u, pub.getNumSubscribers()) << "subscribed to the input with no output subscriber";
  pub.publish(copyOf(*frames()[0]));
  ros::WallDuration(0.3).sleep();
  EXPECT_EQ(0u, rc->stats().frames_received);

  {
    Collector out("/rc_lazy");
    ASSERT_TRUE(waitUntil([&] { return pub.getNumSubscribers() > 0; }));
    pub.publish(copyOf(*frames()[1]));
    ASSERT_TRUE(waitUntil([&] { return out.complete(1); }));
    EXPECT_EQ(1u, rc->stats().frames_processed);
  }
  // Collector gone: the nodelet must let go of the input again.
  EXPECT_TRUE(waitUntil([&] { return pub.getNumSubscribers() == 0; }));
  pub.publish(copyOf(*frames()[2]));
  ros::WallDuration(0.3).sleep();
  EXPECT_EQ(1u, rc->stats().frames_received);
}

TEST(NodeletInProcess, TwoInstancesInOneManagerAreIndependent)
{
  // Instance b keeps only large primitives: if parameters or state were shared, a would too.
  ros::param::set("/rc_b/min_primitive_points", 200);
  Manager m;
  auto a = m.load("/rc_a", "/input_a");
  auto b = m.load("/rc_b", "/input_b");
  ASSERT_TRUE(a && b);
  ros::NodeHandle nh;
  ros::Publisher pa = nh.advertise<PointCloud2>("/input_a", 1), pb = nh.advertise<PointCloud2>("/input_b", 1);
  Collector oa("/rc_a"), ob("/rc_b");
  ASSERT_TRUE(waitUntil([&] { return pa.getNumSubscribers() > 0 && pb.getNumSubscribers() > 0; }));

  pa.publish(copyOf(*frames()[0]));
  ASSERT_TRUE(waitUntil([&] { return oa.complete(1); }));
  ros::WallDuration(0.2).sleep();
  EXPECT_EQ(0u, ob.total()) << "a frame on a's input came out of b";
  pb.publish(copyOf(*frames()[0]));
  ASSERT_TRUE(waitUntil([&] { return ob.complete(1); }));
  EXPECT_EQ(1u, a->stats().frames_processed);
  EXPECT_EQ(1u, b->stats().frames_processed);

  std::lock_guard<std::mutex> la(oa.mutex), lb(ob.mutex);
  const auto& pa_msg = *oa.primitives[0];
  const auto& pb_msg = *ob.primitives[0];
  EXPECT_LT(pb_msg.primitives.size(), pa_msg.primitives.size());
  std::size_t small_in_a = 0;
  for (const auto& p : pa_msg.primitives)
    small_in_a += p.num_points < 200;
  EXPECT_GT(small_in_a, 0u) << "a should keep small primitives (default min_primitive_points)";
  for (const auto& p : pb_msg.primitives)
    EXPECT_GE(p.num_points, 200u);
  ros::param::del("/rc_b");
}

TEST(NodeletInProcess, RingTypesReorderedFieldsAndABadFrame)
{
  Manager m;
  auto rc = m.load("/rc_types", "/input_types");
  ASSERT_TRUE(rc);
  ros::NodeHandle nh;
  ros::Publisher pub = nh.advertise<PointCloud2>("/input_types", 1);
  Collector out("/rc_types");
  ASSERT_TRUE(waitUntil([&] { return pub.getNumSubscribers() > 0; }));

  std::size_t expected = 0;
  for (std::uint8_t t : {sensor_msgs::PointField::UINT8, sensor_msgs::PointField::UINT16,
                         sensor_msgs::PointField::INT32})
  {
    const auto in = relayout(*frames()[0], t);
    pub.publish(in);
    ++expected;
    ASSERT_TRUE(waitUntil([&] { return out.complete(expected); })) << "ring datatype " << int(t);
    std::lock_guard<std::mutex> l(out.mutex);
    checkLabelled(*in, *out.labelled.back());
    checkPrimitives(*out.labelled.back(), *out.primitives.back());
  }

  // No ring field: rejected, counted, nothing published, the nodelet carries on.
  pub.publish(withoutField(*frames()[1], "ring"));
  ASSERT_TRUE(waitUntil([&] { return rc->stats().frames_rejected == 1; }));
  EXPECT_NE(std::string::npos, rc->stats().last_error.find("ring"));
  ros::WallDuration(0.2).sleep();
  EXPECT_EQ(expected * kOutputTopics, out.total());

  pub.publish(copyOf(*frames()[2]));
  ++expected;
  ASSERT_TRUE(waitUntil([&] { return out.complete(expected); })) << "good frame after a bad one";
  EXPECT_EQ(expected, rc->stats().frames_processed);
}

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
    subs.push_back(nh.subscribe<PointCloud2>(std::string("/rc_loam/loam/") + names[i], 10,
                                             [&, i](const PointCloud2::ConstPtr& c) {
                                               std::lock_guard<std::mutex> l(mutex);
                                               got[i].push_back(c);
                                             }));
  subs.push_back(nh.subscribe<ring_curvature::FrameStats>("/rc_loam/frame_stats", 10,
                                                          [&](const ring_curvature::FrameStats::ConstPtr& st) {
                                                            std::lock_guard<std::mutex> l(mutex);
                                                            stats.push_back(st);
                                                          }));
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

// Deskew (~deskew_odometry): with two recent poses the LOAM clouds move each point by the motion
// up to its firing time (the sweep's start is the stamp here); a frame far from the last pose is
// left as it is and says so on ~frame_stats.
TEST(NodeletInProcess, LoamCloudsDeskewedWithRecentOdometry)
{
  Manager m;
  DeskewPair d(m, "/rc_deskew", "/input_deskew", "/odom_deskew");
  ASSERT_TRUE(d.loaded && d.connected());
  const ros::Time stamp = frames()[0]->header.stamp;
  d.drive(stamp);
  ASSERT_TRUE(d.publishAndWait(stamp));
  {
    std::lock_guard<std::mutex> l(d.mutex);
    EXPECT_TRUE(d.stats->deskewed);
    std::size_t early = 0, late = 0;
    d.eachDifference([&](std::uint32_t k, float dx, float dy, float dz, float t) {
      // moved forward by the distance driven since the sweep began, sideways and up not at all
      EXPECT_NEAR(dx, 6.0f * t, 2e-3f) << "at " << k;
      EXPECT_NEAR(dy, 0.0f, 1e-3f);
      EXPECT_NEAR(dz, 0.0f, 1e-3f);
      early += t < 0.01f ? 1 : 0;
      late += t > 0.09f ? 1 : 0;
    });
    EXPECT_GT(early, 100u);
    EXPECT_GT(late, 100u);
  }
  // ten seconds after the last pose: no motion model, the points as they are
  ASSERT_TRUE(d.publishAndWait(stamp + ros::Duration(10.0)));
  std::lock_guard<std::mutex> l(d.mutex);
  EXPECT_FALSE(d.stats->deskewed);
  ASSERT_EQ(d.got[0]->width, d.got[1]->width);
  EXPECT_EQ(0, std::memcmp(d.got[0]->data.data(), d.got[1]->data.data(), d.got[0]->data.size()));
}

// Deskew with the odometry of a base (~deskew_use_tf): no deskew until tf has the LiDAR's
// mounting, then the base's forward motion moves the points along the LiDAR's own axis (-y: it is
// mounted turned by 90 degrees).
TEST(NodeletInProcess, LoamCloudsDeskewedWithBaseOdometryThroughTf)
{
  Manager m;
  ros::param::set("/rc_base/deskew_use_tf", true);
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

TEST(NodeletInProcess, InvalidParameterFailsLoudlyAtStartup)
{
  ros::param::set("/rc_bad/smoothness_window", -3);
  Manager m;
  bool loaded = false;
  try
  {
    loaded = static_cast<bool>(m.load("/rc_bad", "/input_bad"));
  }
  catch (const std::exception&)
  {
    loaded = false;  // onInit throws (after NODELET_FATAL naming the parameter)
  }
  EXPECT_FALSE(loaded);
  ros::param::del("/rc_bad");
}

TEST(NodeletInProcess, FieldListsAsYamlListsOrBracketedStrings)
{
  // A launch file's YAML list and rosrun's `_ring_field:=[beam,ring]` (which roscpp leaves a
  // string) both mean the list "beam,ring".
  XmlRpc::XmlRpcValue list;
  list[0] = "beam";
  list[1] = "ring";
  ros::param::set("/rc_lists/ring_field", list);
  ros::param::set("/rc_lists/time_field", std::string("['stamp', t]"));
  ring_curvature::Params p;
  ASSERT_TRUE(ring_curvature::loadParams(ros::NodeHandle("/rc_lists"), p).ok);
  EXPECT_EQ(p.ring_field, "beam,ring");
  EXPECT_EQ(p.time_field, "stamp, t");
  ros::param::set("/rc_lists/ring_field", std::string("[beam,ring]"));
  ASSERT_TRUE(ring_curvature::loadParams(ros::NodeHandle("/rc_lists"), p).ok);
  EXPECT_EQ(p.ring_field, "beam,ring");
  ros::param::set("/rc_lists/ring_field", std::string("[]"));
  EXPECT_FALSE(ring_curvature::loadParams(ros::NodeHandle("/rc_lists"), p).ok) << "an empty list names no field";
  ros::param::del("/rc_lists");
}

int main(int argc, char** argv)
{
  testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "test_nodelet_inprocess");
  ros::AsyncSpinner spinner(2);
  spinner.start();
  const int r = RUN_ALL_TESTS();
  spinner.stop();
  ros::shutdown();
  return r;
}
