// The ROS layer without a ROS master: cloud adapter checks, the output message layouts, and
// parameter loading (the shipped YAML must hold exactly the core's defaults).
#include <gtest/gtest.h>
#include <ros/package.h>
#include <ros/serialization.h>

#include <map>

#include "ring_curvature/PrimitiveArray.h"
#include "ring_curvature/ros/cloud_adapter.hpp"
#include "ring_curvature/ros/frame_processor.hpp"
#include "cloud_builders.hpp"
#include "output_checks.hpp"

using namespace ring_curvature;
using namespace ring_curvature_test;

namespace
{

std::string fixture(const std::string& name) { return std::string(RC_SOURCE_DIR) + "/rosbag_fixtures/" + name; }

const sensor_msgs::PointCloud2& vlp16Frame()
{
  static const auto clouds = readClouds(fixture("nebula_vlp16_lastreturn_4scans.bag"), "/velodyne_points");
  return *clouds.at(0);
}

}  // namespace

TEST(CloudAdapter, ReadsPackedVelodyneLayoutInPlace)
{
  const auto& msg = vlp16Frame();
  PointCloudView v;
  const Status s = makeView(msg, Params(), v);
  ASSERT_TRUE(s.ok) << s.message;
  EXPECT_EQ(msg.data.data(), v.data) << "the view must point into the message, not a copy";
  EXPECT_EQ(22u, v.point_step);
  EXPECT_EQ(16, v.ring.offset);
  EXPECT_EQ(ScalarType::UInt16, v.ring.type);
  EXPECT_EQ(18, v.time.offset);
  EXPECT_EQ(12, v.intensity.offset);
}

TEST(CloudAdapter, AcceptsIntegerRingTypesAndReorderedFields)
{
  for (std::uint8_t t : {sensor_msgs::PointField::UINT8, sensor_msgs::PointField::INT16,
                         sensor_msgs::PointField::UINT16, sensor_msgs::PointField::INT32})
  {
    const auto c = relayout(vlp16Frame(), t);
    PointCloudView v;
    const Status s = makeView(*c, Params(), v);
    ASSERT_TRUE(s.ok) << s.message;
    EXPECT_EQ(static_cast<ScalarType>(t), v.ring.type);
    EXPECT_GT(v.x.offset, v.ring.offset) << "fields were reordered: x comes after ring";
  }
}

TEST(CloudAdapter, RejectsFloatRingWithAdvice)
{
  auto c = relayout(vlp16Frame(), sensor_msgs::PointField::FLOAT32);
  PointCloudView v;
  const Status s = makeView(*c, Params(), v);
  ASSERT_FALSE(s.ok);
  EXPECT_NE(std::string::npos, s.message.find("ring")) << s.message;
  EXPECT_NE(std::string::npos, s.message.find("integer")) << s.message;
}

TEST(CloudAdapter, MissingRingListsFieldsAndRemedies)
{
  const auto c = withoutField(vlp16Frame(), "ring");
  PointCloudView v;
  Status s = makeView(*c, Params(), v);
  ASSERT_FALSE(s.ok);
  EXPECT_NE(std::string::npos, s.message.find("intensity:float32")) << s.message;
  EXPECT_NE(std::string::npos, s.message.find("ring_from_elevation")) << s.message;
  Params p;
  p.ring_from_elevation = true;
  s = makeView(*c, p, v);
  EXPECT_TRUE(s.ok) << s.message;
  EXPECT_FALSE(v.ring.present());
}

TEST(CloudAdapter, OrganizedCloudMayOmitRing)
{
  auto c = withoutField(vlp16Frame(), "ring");
  // 14 rows of equal width stand in for an organized cloud; only the layout matters here.
  c->height = 2;
  c->width = vlp16Frame().width / 2;
  c->row_step = c->width * c->point_step;
  c->data.resize(static_cast<std::size_t>(c->row_step) * c->height);
  PointCloudView v;
  const Status s = makeView(*c, Params(), v);
  EXPECT_TRUE(s.ok) << s.message;
}

TEST(CloudAdapter, RejectsInconsistentLayouts)
{
  PointCloudView v;
  auto c = boost::make_shared<sensor_msgs::PointCloud2>(vlp16Frame());
  c->is_bigendian = true;
  EXPECT_NE(std::string::npos, makeView(*c, Params(), v).message.find("big-endian"));

  c = boost::make_shared<sensor_msgs::PointCloud2>(vlp16Frame());
  c->data.pop_back();
  EXPECT_NE(std::string::npos, makeView(*c, Params(), v).message.find("truncated"));

  c = boost::make_shared<sensor_msgs::PointCloud2>(vlp16Frame());
  c->row_step -= 1;
  EXPECT_FALSE(makeView(*c, Params(), v).ok);

  c = boost::make_shared<sensor_msgs::PointCloud2>(vlp16Frame());
  c->fields.back().offset = c->point_step - 2;  // the 4-byte time field now ends past the record
  const Status s = makeView(*c, Params(), v);
  EXPECT_NE(std::string::npos, s.message.find("past point_step")) << s.message;

  c = withoutField(vlp16Frame(), "x");
  EXPECT_NE(std::string::npos, makeView(*c, Params(), v).message.find("'x'"));
}

TEST(Outputs, AllOutputsAgreeWithTheInput)
{
  FrameProcessor proc;
  for (std::uint8_t t : {sensor_msgs::PointField::UINT16, sensor_msgs::PointField::UINT8})
  {
    const auto in = relayout(vlp16Frame(), t);
    Outputs out;
    const Status s = proc.process(*in, out);
    ASSERT_TRUE(s.ok) << s.message;
    ASSERT_TRUE(out.labelled && out.primitives && out.edges && out.planes);
    checkLabelled(*in, *out.labelled);
    checkPrimitives(*out.labelled, *out.primitives);
    checkSubset(*in, *out.labelled, *out.edges, 2, 3, "edges");
    checkSubset(*in, *out.labelled, *out.planes, 1, 1, "planes");
    EXPECT_GT(out.planes->width, 0u) << "an indoor scene has planes";
    EXPECT_EQ(0u, out.labelled->point_step % 4);
  }
}

TEST(Outputs, RingTypeAndFieldOrderDoNotChangeLabels)
{
  FrameProcessor proc;
  Outputs a, b;
  ASSERT_TRUE(proc.process(vlp16Frame(), a).ok);
  const auto re = relayout(vlp16Frame(), sensor_msgs::PointField::INT32);
  ASSERT_TRUE(proc.process(*re, b).ok);
  const auto* la = field(*a.labelled, "label");
  const auto* lb = field(*b.labelled, "label");
  std::size_t differ = 0;
  for (std::size_t i = 0; i < a.labelled->width; ++i)
    differ += get<std::uint8_t>(*a.labelled, i, *la) != get<std::uint8_t>(*b.labelled, i, *lb);
  EXPECT_EQ(0u, differ);
  EXPECT_EQ(a.primitives->primitives.size(), b.primitives->primitives.size());
}

// The bytes a message would go out with (what a subscriber in another process receives).
template <class M>
std::vector<std::uint8_t> wire(const M& m)
{
  const ros::SerializedMessage s = ros::serialization::serializeMessage(m);
  return std::vector<std::uint8_t>(s.buf.get(), s.buf.get() + s.num_bytes);
}

void expectSameOutputs(const Outputs& a, const Outputs& b)
{
  EXPECT_EQ(wire(*a.labelled), wire(*b.labelled));
  EXPECT_EQ(wire(*a.primitives), wire(*b.primitives));
  EXPECT_EQ(wire(*a.edges), wire(*b.edges));
  EXPECT_EQ(wire(*a.planes), wire(*b.planes));
  EXPECT_EQ(wire(*a.markers), wire(*b.markers));
}

// The processor fills the last frame's messages again (ros/recycle.hpp), but only those no one
// else holds: a message a subscriber kept must never change under it, and a recycled one must
// come out exactly as a new one would.
TEST(Outputs, RecycledOnlyWhenNoOneElseHoldsThem)
{
  const auto clouds = readClouds(fixture("nebula_vlp16_lastreturn_4scans.bag"), "/velodyne_points");
  ASSERT_GE(clouds.size(), 3u);
  FrameProcessor proc;
  Outputs first;
  ASSERT_TRUE(proc.process(*clouds[0], first).ok);
  const Outputs kept = first;  // a subscriber that holds on to every message of frame 0
  const std::vector<std::uint8_t> kept_bytes = wire(*kept.labelled), kept_markers = wire(*kept.markers);
  first = Outputs();

  Outputs second;
  ASSERT_TRUE(proc.process(*clouds[1], second).ok);
  EXPECT_NE(kept.labelled.get(), second.labelled.get());
  EXPECT_NE(kept.planes.get(), second.planes.get());
  EXPECT_NE(kept.primitives.get(), second.primitives.get());
  EXPECT_NE(kept.markers.get(), second.markers.get());
  EXPECT_EQ(kept_bytes, wire(*kept.labelled)) << "a held message changed";
  EXPECT_EQ(kept_markers, wire(*kept.markers)) << "a held message changed";

  // frame 1's messages are dropped by everyone: frame 2 fills them again, bytes as from new
  const void* const labelled = second.labelled.get();
  const void* const markers = second.markers.get();
  second = Outputs();
  Outputs third, fresh;
  ASSERT_TRUE(proc.process(*clouds[2], third).ok);
  EXPECT_EQ(labelled, third.labelled.get());
  EXPECT_EQ(markers, third.markers.get());
  FrameProcessor other;
  ASSERT_TRUE(other.process(*clouds[2], fresh).ok);
  expectSameOutputs(third, fresh);
}
