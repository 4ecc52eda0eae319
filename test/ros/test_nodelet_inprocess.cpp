// RingCurvatureNodelet inside a nodelet::Loader in this test process (a nodelet manager), fed by
// a publisher in the same process: outputs per frame, zero copy (the nodelet reads the very
// buffer published and subscribers get the very objects it published), laziness, two
// independent instances, ring datatypes / reordered fields, and a bad frame followed by a good one.
// (The LOAM outputs and their deskewing: test_nodelet_inprocess_loam.cpp.)
#include <gtest/gtest.h>
#include <ros/ros.h>
#include <visualization_msgs/MarkerArray.h>

#include <cstdint>
#include <exception>
#include <mutex>
#include <string>
#include <vector>

#include "ring_curvature/ros/param_loading.hpp"
#include "ring_curvature/ros/ring_curvature_nodelet.hpp"
#include "cloud_builders.hpp"
#include "keep_messages.hpp"
#include "nodelet_harness.hpp"
#include "output_checks.hpp"

using namespace ring_curvature_test;
using sensor_msgs::PointCloud2;

namespace
{

// labelled_points, primitives, edges, planes, markers, frame_stats
constexpr std::size_t kOutputTopics = 6;

// Keeps every message received on the outputs of one nodelet.
struct Collector
{
  explicit Collector(const std::string& ns)
  {
    ros::NodeHandle nh;
    subs = {keepMessages<PointCloud2>(nh, ns + "/labelled_points", mutex, labelled),
            keepMessages<ring_curvature::PrimitiveArray>(nh, ns + "/primitives", mutex, primitives),
            keepMessages<PointCloud2>(nh, ns + "/edges", mutex, edges),
            keepMessages<PointCloud2>(nh, ns + "/planes", mutex, planes),
            keepMessages<visualization_msgs::MarkerArray>(nh, ns + "/markers", mutex, markers),
            keepMessages<ring_curvature::FrameStats>(nh, ns + "/frame_stats", mutex, stats)};
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

TEST(NodeletInProcess, InvalidParameterFailsLoudlyAtStartup)
{
  // a core parameter, and a nodelet one
  for (const auto& [key, value] : {std::pair<std::string, XmlRpc::XmlRpcValue>{"smoothness_window", -3},
                                   std::pair<std::string, XmlRpc::XmlRpcValue>{"deskew_reference", "start"}})
  {
    ros::param::set("/rc_bad/" + key, value);
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
    EXPECT_FALSE(loaded) << key;
    ros::param::del("/rc_bad");
  }
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

int main(int argc, char** argv) { return runTests(argc, argv, "test_nodelet_inprocess"); }
