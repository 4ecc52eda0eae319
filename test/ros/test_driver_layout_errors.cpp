// The adapter's rejections of driver layouts it cannot read (no ring field, a ring of the wrong
// type, a ring or time with several values per point): each message names the field, what is
// wrong with it and the parameter that would fix it.
#include <gtest/gtest.h>
#include <sensor_msgs/PointField.h>

#include <string>

#include "driver_layouts.hpp"
#include "ring_curvature/pipeline.hpp"
#include "ring_curvature/ros/cloud_adapter.hpp"

using namespace ring_curvature;
using namespace ring_curvature::test;

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
