// The adapter against the point layouts real drivers publish (field names, datatypes, offsets and
// point_step as each driver lays them out), and the parameters that name the ring and time fields
// (ring_field, time_field, time_unit). The geometry is the synthetic room scan of the robustness
// tests, so every layout carries the same points and must give the same labels.
// (Rejected layouts: test_driver_layout_errors.cpp.)
#include <gtest/gtest.h>
#include <sensor_msgs/PointField.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "driver_layouts.hpp"
#include "ring_curvature/pipeline.hpp"
#include "ring_curvature/ros/cloud_adapter.hpp"
#include "ring_curvature/ros/frame_processor.hpp"
#include "ring_curvature/ros/param_loading.hpp"

using namespace ring_curvature;
using namespace ring_curvature::test;

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
