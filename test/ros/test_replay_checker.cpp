// Checker for bag replays (rosbag play -> ring_curvature node or nodelet): every frame of the
// bag comes out exactly once on each output topic with its stamp and frame_id, and the outputs
// agree with the frame. The frames are read from the bag itself (~bag, ~topic), so the checker
// does not subscribe to the input and rosbag play --wait-for-subscribers waits for the nodelet.
#include <gtest/gtest.h>
#include <ros/ros.h>
#include <visualization_msgs/MarkerArray.h>

#include <map>
#include <mutex>

#include "cloud_builders.hpp"
#include "keep_messages.hpp"
#include "output_checks.hpp"

using namespace ring_curvature_test;
using sensor_msgs::PointCloud2;

namespace
{

struct Received
{
  std::vector<PointCloud2::ConstPtr> labelled, edges, planes;
  std::vector<ring_curvature::PrimitiveArray::ConstPtr> primitives;
  std::vector<visualization_msgs::MarkerArray::ConstPtr> markers;
};

template <class Ptr>
Ptr byStamp(const std::vector<Ptr>& v, const ros::Time& t)
{
  for (const auto& m : v)
    if (m->header.stamp == t)
      return m;
  return nullptr;
}

}  // namespace

TEST(Replay, EveryFrameOnceOnEveryOutput)
{
  ros::NodeHandle pnh("~");
  std::string bag, topic = "/velodyne_points", ns = "/ring_curvature";
  double timeout = 30.0;
  ASSERT_TRUE(pnh.getParam("bag", bag));
  pnh.getParam("topic", topic);
  pnh.getParam("output_ns", ns);
  pnh.getParam("timeout", timeout);
  const auto frames = readClouds(bag, topic);
  ASSERT_FALSE(frames.empty());

  std::mutex mutex;
  Received r;
  ros::NodeHandle nh;
  std::vector<ros::Subscriber> subs;
  subs.push_back(keepMessages<PointCloud2>(nh, ns + "/labelled_points", mutex, r.labelled));
  subs.push_back(keepMessages<ring_curvature::PrimitiveArray>(nh, ns + "/primitives", mutex, r.primitives));
  subs.push_back(keepMessages<PointCloud2>(nh, ns + "/edges", mutex, r.edges));
  subs.push_back(keepMessages<PointCloud2>(nh, ns + "/planes", mutex, r.planes));
  subs.push_back(keepMessages<visualization_msgs::MarkerArray>(nh, ns + "/markers", mutex, r.markers));

  const std::size_t n = frames.size();
  const ros::WallTime end = ros::WallTime::now() + ros::WallDuration(timeout);
  for (;;)
  {
    {
      std::lock_guard<std::mutex> l(mutex);
      if (r.labelled.size() >= n && r.primitives.size() >= n && r.edges.size() >= n && r.planes.size() >= n &&
          r.markers.size() >= n)
        break;
    }
    ASSERT_LT(ros::WallTime::now(), end) << "timed out: got " << r.labelled.size() << " labelled clouds for " << n
                                         << " frames";
    ros::WallDuration(0.01).sleep();
  }
  ros::WallDuration(0.5).sleep();  // nothing extra may trail in

  std::lock_guard<std::mutex> l(mutex);
  EXPECT_EQ(n, r.labelled.size());
  EXPECT_EQ(n, r.primitives.size());
  EXPECT_EQ(n, r.edges.size());
  EXPECT_EQ(n, r.planes.size());
  EXPECT_EQ(n, r.markers.size());
  for (const auto& in : frames)
  {
    SCOPED_TRACE("frame stamped " + std::to_string(in->header.stamp.toSec()));
    const auto lab = byStamp(r.labelled, in->header.stamp);
    const auto prim = byStamp(r.primitives, in->header.stamp);
    const auto edges = byStamp(r.edges, in->header.stamp);
    const auto planes = byStamp(r.planes, in->header.stamp);
    ASSERT_TRUE(lab && prim && edges && planes) << "an output is missing for this stamp";
    checkLabelled(*in, *lab);
    checkPrimitives(*lab, *prim);
    checkSubset(*in, *lab, *edges, 2, 3, "edges");
    checkSubset(*in, *lab, *planes, 1, 1, "planes");
  }
}

int main(int argc, char** argv)
{
  testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "replay_checker");
  ros::AsyncSpinner spinner(1);
  spinner.start();
  return RUN_ALL_TESTS();
}
