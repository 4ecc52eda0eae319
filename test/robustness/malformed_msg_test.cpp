// Malformed sensor_msgs/PointCloud2 through the ROS input adapter and everything the nodelet
// runs per frame (FrameProcessor: makeView -> Pipeline -> output messages), without a master.
// Each bad message: rejected with a message naming the problem, no output built; the next good
// message gives byte-identical outputs to a fresh processor's (PrimitiveArray: compared by
// count through FrameProcessor::summary()).
#include <gtest/gtest.h>

#include <functional>
#include <limits>

#include "cloud_msg.hpp"
#include "expectations.hpp"
#include "ring_curvature/ros/frame_processor.hpp"

namespace rc = ring_curvature;
using rc::test::field;
using rc::test::mentionsAny;
using rc::test::mentionsToken;
using Msg = sensor_msgs::PointCloud2;

namespace
{

Msg goodMsg(int rings = 16, int samples = 360) { return rc::test::toMsg(rc::test::goodCloud(rings, samples)); }

void expectSameOutputs(const rc::Outputs& a, const rc::Outputs& b)
{
  ASSERT_TRUE(a.labelled && b.labelled && a.primitives && b.primitives && a.edges && b.edges &&
              a.planes && b.planes && a.markers && b.markers);
  EXPECT_EQ(a.labelled->data, b.labelled->data);
  EXPECT_EQ(a.labelled->fields.size(), b.labelled->fields.size());
  EXPECT_EQ(a.edges->data, b.edges->data);
  EXPECT_EQ(a.planes->data, b.planes->data);
  EXPECT_EQ(a.markers->markers.size(), b.markers->markers.size());
}

struct Case
{
  const char* name;
  std::function<void(Msg&)> corrupt;
  std::vector<const char*> words;  ///< the message must contain one of these (case-insensitive)
  const char* token = nullptr;     ///< ... and, if set, this whole word (a field name)
};

std::vector<Case> cases()
{
  using T = sensor_msgs::PointField;
  return {
      {"no ring field", [](Msg& m) { m.fields.erase(m.fields.begin() + 4); }, {"ring"}, "ring"},
      {"ring float32", [](Msg& m) { field(m, "ring")->datatype = T::FLOAT32; field(m, "ring")->offset = 18;
                                    m.fields.pop_back(); /* time moved out of the way */ },
       {"integer", "type"}, "ring"},
      {"ring float64", [](Msg& m) { field(m, "ring")->datatype = T::FLOAT64; }, {"ring"}, "ring"},
      {"ring >= max_rings",
       [](Msg& m) { const std::uint16_t big = 256; std::memcpy(m.data.data() + 22 * 77 + 16, &big, 2); },
       {"max_rings"}, "ring"},
      {"negative ring",
       [](Msg& m) { field(m, "ring")->datatype = T::INT16; const std::int16_t neg = -3;
                    std::memcpy(m.data.data() + 22 * 5 + 16, &neg, 2); },
       {"ring"}, "ring"},
      {"no x", [](Msg& m) { m.fields.erase(m.fields.begin()); }, {"x"}, "x"},
      {"no y", [](Msg& m) { field(m, "y")->name = "yy"; }, {"y"}, "y"},
      {"no z", [](Msg& m) { m.fields.erase(m.fields.begin() + 2); }, {"z"}, "z"},
      {"x uint32", [](Msg& m) { field(m, "x")->datatype = T::UINT32; }, {"float"}, "x"},
      {"unknown datatype", [](Msg& m) { field(m, "intensity")->datatype = 9; }, {"datatype"}, "intensity"},
      {"datatype 0", [](Msg& m) { field(m, "z")->datatype = 0; }, {"datatype"}, "z"},
      {"z past point_step", [](Msg& m) { field(m, "z")->offset = 20; }, {"point_step"}, "z"},
      {"offset 2^32-1", [](Msg& m) { field(m, "x")->offset = 0xFFFFFFFFu; }, {"point_step"}, "x"},
      {"count past point_step", [](Msg& m) { field(m, "intensity")->count = 1000; }, {"point_step"}, "intensity"},
      {"time past point_step", [](Msg& m) { field(m, "time")->offset = 19; }, {"point_step"}, "time"},
      {"y overlaps x and z", [](Msg& m) { field(m, "y")->offset = 2; }, {"overlap"}},
      {"ring aliases z", [](Msg& m) { field(m, "ring")->offset = 8; }, {"overlap"}},
      {"point_step 0", [](Msg& m) { m.point_step = 0; }, {"point_step"}},
      {"row_step too small", [](Msg& m) { m.row_step -= 1; }, {"row_step"}},
      {"row_step 0", [](Msg& m) { m.row_step = 0; }, {"row_step"}},
      {"truncated by one byte", [](Msg& m) { m.data.pop_back(); }, {"truncated", "bytes"}},
      {"half the data", [](Msg& m) { m.data.resize(m.data.size() / 2); }, {"truncated", "bytes"}},
      {"no data", [](Msg& m) { m.data.clear(); }, {"truncated", "bytes"}},
      {"oversized data", [](Msg& m) { m.data.resize(m.data.size() + 100); }, {"bytes", "row_step"}},
      {"width larger than data", [](Msg& m) { m.width *= 2; }, {"bytes", "row_step"}},
      {"height larger than data", [](Msg& m) { m.height = 3; }, {"bytes", "truncated"}},
      {"width * point_step overflows", [](Msg& m) { m.width = 0x80000000u; m.row_step = 0xFFFFFFFFu; },
       {"bytes", "row_step"}},
      {"big-endian", [](Msg& m) { m.is_bigendian = true; }, {"endian"}},
      {"no fields at all", [](Msg& m) { m.fields.clear(); }, {"x"}, "x"},
  };
}

class MalformedMsg : public ::testing::Test
{
protected:
  void SetUp() override
  {
    good_ = goodMsg(32, 1024);
    rc::FrameProcessor fresh;
    const rc::Status st = fresh.process(good_, ref_);
    ASSERT_TRUE(st.ok) << st.message;
    ref_primitives_ = fresh.summary().primitives;
    ASSERT_GT(ref_primitives_, 0u);
  }
  Msg good_;
  rc::Outputs ref_;
  std::size_t ref_primitives_ = 0;
};

TEST_F(MalformedMsg, EachIsRejectedNamingTheProblemAndTheNextFrameIsRight)
{
  rc::FrameProcessor processor;
  rc::Outputs out;
  ASSERT_TRUE(processor.process(goodMsg(), out).ok);
  for (const Case& c : cases())
  {
    SCOPED_TRACE(c.name);
    Msg bad = goodMsg();
    c.corrupt(bad);
    const rc::Status st = processor.process(bad, out);
    EXPECT_FALSE(st.ok) << "accepted";
    bool named = false;
    for (const char* w : c.words)
      named = named || mentionsAny(st.message, {w});
    EXPECT_TRUE(named) << st.message;
    if (c.token)
    {
      EXPECT_TRUE(mentionsToken(st.message, c.token)) << st.message;
    }
    EXPECT_FALSE(out.labelled || out.primitives || out.edges || out.planes || out.markers)
        << "a rejected frame produced output";
    std::printf("%-28s -> %s\n", c.name, st.message.c_str());

    const rc::Status next = processor.process(good_, out);
    ASSERT_TRUE(next.ok) << next.message;
    expectSameOutputs(out, ref_);
    EXPECT_EQ(processor.summary().primitives, ref_primitives_);
  }
}

TEST_F(MalformedMsg, DegenerateButLegalFramesAreProcessed)
{
  std::vector<std::pair<const char*, Msg>> legal;
  legal.emplace_back("one point", rc::test::toMsg(rc::test::pack(rc::test::roomScan(1, 1),
                                                                 rc::test::velodyneLayout(), 1, 1)));
  legal.emplace_back("single ring", rc::test::toMsg(rc::test::goodCloud(1, 1800)));
  {
    auto pts = rc::test::roomScan(16, 360);
    for (auto& p : pts)
      p.x = p.y = p.z = std::numeric_limits<float>::quiet_NaN();
    legal.emplace_back("all NaN", rc::test::toMsg(rc::test::pack(pts, rc::test::velodyneLayout(), 16 * 360, 1)));
    for (auto& p : pts)
    {
      p.x = 2.0f;
      p.y = 1.0f;
      p.z = 0.0f;
    }
    legal.emplace_back("all identical",
                       rc::test::toMsg(rc::test::pack(pts, rc::test::velodyneLayout(), 16 * 360, 1)));
  }
  {
    // ouster-ros layout, organized, time as "t" uint32 ns
    const auto pts = rc::test::toOrganized(rc::test::roomScan(32, 1024), 32, 1024);
    legal.emplace_back("ouster organized",
                       rc::test::toMsg(rc::test::pack(pts, rc::test::ousterLayout(), 1024, 32), "t"));
  }
  {
    Msg m = goodMsg();
    field(m, "x")->count = 0;  // count 0 is seen in the wild and means 1
    legal.emplace_back("count 0", m);
  }
  {
    Msg m = goodMsg();
    m.fields.erase(m.fields.begin() + 3);  // no intensity, no time: both optional
    m.fields.pop_back();
    legal.emplace_back("no optional fields", m);
  }
  for (auto& [name, msg] : legal)
  {
    SCOPED_TRACE(name);
    rc::FrameProcessor processor;
    rc::Outputs out;
    const rc::Status st = processor.process(msg, out);
    ASSERT_TRUE(st.ok) << st.message;
    ASSERT_TRUE(out.labelled);
    EXPECT_EQ(out.labelled->width, msg.width);
    EXPECT_EQ(out.labelled->height, msg.height);
    EXPECT_EQ(out.labelled->data.size(),
              static_cast<std::size_t>(out.labelled->row_step) * out.labelled->height);
    EXPECT_EQ(out.labelled->header.stamp, msg.header.stamp);
    rc::test::expectConsistent(processor.result(), static_cast<std::size_t>(msg.width) * msg.height);
  }
}

TEST_F(MalformedMsg, EmptyFramesNeitherCrashNorLeaveState)
{
  for (int which = 0; which < 2; ++which)
  {
    Msg m = goodMsg();
    if (which == 0)
    {
      m.width = 0;  // a row of no points
      m.row_step = 0;
    }
    else
    {
      m.height = 0;
    }
    m.data.clear();
    rc::FrameProcessor processor;
    rc::Outputs out;
    const rc::Status st = processor.process(m, out);
    if (st.ok)
    {
      EXPECT_TRUE(!out.labelled || out.labelled->data.empty());
    }
    else
    {
      EXPECT_TRUE(mentionsAny(st.message, {"empty", "width", "height", "no points"})) << st.message;
    }
    ASSERT_TRUE(processor.process(good_, out).ok);
    expectSameOutputs(out, ref_);
  }
}

TEST_F(MalformedMsg, TwoMillionPoints)
{
  const Msg m = goodMsg(128, 15625);
  rc::FrameProcessor processor;
  rc::Outputs out;
  const rc::Status st = processor.process(m, out);
  ASSERT_TRUE(st.ok) << st.message;
  ASSERT_TRUE(out.labelled);
  EXPECT_EQ(out.labelled->width, 2000000u);
  rc::test::expectConsistent(processor.result(), 2000000u);
}

}  // namespace
