// Malformed clouds through the core (PointCloudView + Pipeline::process): bad fields, bad sizes,
// and invalid parameters. For every bad frame: no crash and no out-of-bounds read (the sanitizer
// build runs this file too), a Status whose message names the problem, an empty result, and a
// pipeline that then processes the next good frame exactly as a fresh pipeline would (degenerate
// but legal frames: degenerate_cloud_test.cpp).
#include <gtest/gtest.h>

#include <limits>
#include <string>
#include <vector>

#include "malformed_fixture.hpp"

namespace rc = ring_curvature;
using rc::test::Cloud;
using rc::test::expectConsistent;
using rc::test::expectSameResult;
using rc::test::Malformed;
using rc::test::mentionsAny;
using rc::test::mentionsToken;

namespace
{

Cloud small() { return rc::test::goodCloud(16, 360); }

// --- fields ---------------------------------------------------------------------------------

TEST_F(Malformed, NoRingFieldInUnorganizedCloud)
{
  Cloud c = small();
  c.layout.ring = {};
  const std::string m = rejectAndRecover(c.view());
  EXPECT_TRUE(mentionsToken(m, "ring")) << m;
}

TEST_F(Malformed, RingOfFloatType)
{
  for (rc::ScalarType t : {rc::ScalarType::Float32, rc::ScalarType::Float64})
  {
    rc::test::Layout l = rc::test::ousterLayout();  // 48 bytes: room for an 8-byte ring
    l.ring = {36, t};
    const Cloud c = rc::test::pack(rc::test::roomScan(16, 360), l, 16 * 360, 1);
    const std::string m = rejectAndRecover(c.view());
    EXPECT_TRUE(mentionsToken(m, "ring")) << m;
    EXPECT_TRUE(mentionsAny(m, {"type", "float", "integer"})) << m;
  }
}

TEST_F(Malformed, RingAboveDefaultMaxRings)
{
  auto pts = rc::test::roomScan(16, 360);
  pts[1000].ring = 300;  // default max_rings is 256
  const Cloud c = rc::test::pack(pts, rc::test::velodyneLayout(), 16 * 360, 1);
  const std::string m = rejectAndRecover(c.view());
  EXPECT_TRUE(mentionsToken(m, "ring")) << m;
  EXPECT_TRUE(mentionsAny(m, {"max_rings"})) << m;
}

TEST_F(Malformed, RingEqualToConfiguredMaxRingsIsRejectedOneBelowIsNot)
{
  rc::Params p;
  p.max_rings = 32;  // the recovery frame has 32 rings
  auto pts = rc::test::roomScan(16, 360);
  pts[7].ring = 32;
  const Cloud bad = rc::test::pack(pts, rc::test::velodyneLayout(), 16 * 360, 1);
  const std::string m = rejectAndRecover(bad.view(), p);
  EXPECT_TRUE(mentionsAny(m, {"max_rings"})) << m;

  pts[7].ring = 31;
  const Cloud ok = rc::test::pack(pts, rc::test::velodyneLayout(), 16 * 360, 1);
  rc::Pipeline pipeline(p);
  rc::FrameResult r;
  const rc::Status st = pipeline.process(ok.view(), r);
  EXPECT_TRUE(st.ok) << st.message;
}

TEST_F(Malformed, NegativeRing)
{
  rc::test::Layout l = rc::test::velodyneLayout();
  l.ring.type = rc::ScalarType::Int16;
  auto pts = rc::test::roomScan(16, 360);
  pts[500].ring = -1;
  const Cloud c = rc::test::pack(pts, l, 16 * 360, 1);
  const std::string m = rejectAndRecover(c.view());
  EXPECT_TRUE(mentionsToken(m, "ring")) << m;
}

TEST_F(Malformed, MissingCoordinate)
{
  for (const char* axis : {"x", "y", "z"})
  {
    Cloud c = small();
    rc::FieldView& f = axis[0] == 'x' ? c.layout.x : axis[0] == 'y' ? c.layout.y : c.layout.z;
    f = {};
    const std::string m = rejectAndRecover(c.view());
    EXPECT_TRUE(mentionsToken(m, axis)) << "missing " << axis << ": " << m;
  }
}

TEST_F(Malformed, CoordinateOfIntegerType)
{
  Cloud c = small();
  c.layout.y.type = rc::ScalarType::UInt32;
  const std::string m = rejectAndRecover(c.view());
  EXPECT_TRUE(mentionsToken(m, "y")) << m;
  EXPECT_TRUE(mentionsAny(m, {"type", "float"})) << m;
}

TEST_F(Malformed, FieldPastPointStep)
{
  // z at 20 in a 22-byte record: its last two bytes would be read from the next point
  Cloud c = small();
  c.layout.z.offset = 20;
  std::string m = rejectAndRecover(c.view());
  EXPECT_TRUE(mentionsToken(m, "z") || mentionsAny(m, {"point_step"})) << m;

  Cloud d = small();
  d.layout.ring.offset = 21;  // uint16 at 21..22 of a 22-byte record
  m = rejectAndRecover(d.view());
  EXPECT_TRUE(mentionsToken(m, "ring") || mentionsAny(m, {"point_step"})) << m;

  Cloud e = small();
  e.layout.x.offset = 1000;  // far outside: must be rejected before any read
  m = rejectAndRecover(e.view());
  EXPECT_TRUE(mentionsToken(m, "x") || mentionsAny(m, {"point_step"})) << m;
}

TEST_F(Malformed, OptionalFieldPastPointStep)
{
  // the core does not need time or intensity, but a view that claims them outside the record
  // is corrupt, and whoever reads them next (outputs, deskewing) would read out of bounds
  Cloud c = small();
  c.layout.time.offset = 19;  // float32 at 19..22
  std::string m = rejectAndRecover(c.view());
  EXPECT_TRUE(mentionsToken(m, "time") || mentionsAny(m, {"point_step"})) << m;

  Cloud d = small();
  d.layout.intensity.offset = 22;
  m = rejectAndRecover(d.view());
  EXPECT_TRUE(mentionsToken(m, "intensity") || mentionsAny(m, {"point_step"})) << m;
}

TEST_F(Malformed, FieldsOverlap)
{
  Cloud c = small();
  c.layout.y.offset = 2;  // y straddles x and z
  std::string m = rejectAndRecover(c.view());
  EXPECT_TRUE(mentionsAny(m, {"overlap"})) << m;

  Cloud d = small();
  d.layout.ring.offset = 8;  // ring aliases z
  m = rejectAndRecover(d.view());
  EXPECT_TRUE(mentionsAny(m, {"overlap"})) << m;
}

// --- sizes ----------------------------------------------------------------------------------

TEST_F(Malformed, PointStepZero)
{
  Cloud c = small();
  c.point_step = 0;
  const std::string m = rejectAndRecover(c.view());
  EXPECT_TRUE(mentionsAny(m, {"point_step"})) << m;
}

TEST_F(Malformed, RowStepSmallerThanRow)
{
  Cloud c = small();
  c.row_step = c.width * c.point_step - 1;
  const std::string m = rejectAndRecover(c.view());
  EXPECT_TRUE(mentionsAny(m, {"row_step"})) << m;
}

TEST_F(Malformed, TruncatedData)
{
  Cloud c = small();
  rc::PointCloudView v = c.view();
  v.data_size -= 1;  // the last point's last byte is missing
  std::string m = rejectAndRecover(v);
  EXPECT_TRUE(mentionsAny(m, {"data", "size", "bytes", "truncated"})) << m;

  v.data_size = c.data.size() / 2;
  m = rejectAndRecover(v);
  EXPECT_TRUE(mentionsAny(m, {"data", "size", "bytes", "truncated"})) << m;

  v.data = nullptr;
  v.data_size = 0;
  m = rejectAndRecover(v);
  EXPECT_FALSE(m.empty());
}

TEST_F(Malformed, OrganizedRowsTruncated)
{
  auto pts = rc::test::toOrganized(rc::test::roomScan(16, 360), 16, 360);
  const Cloud c = rc::test::pack(pts, rc::test::velodyneLayout(), 360, 16);
  rc::PointCloudView v = c.view();
  v.data_size = static_cast<std::size_t>(v.row_step) * 15 + v.point_step * 359;  // last point cut
  const std::string m = rejectAndRecover(v);
  EXPECT_TRUE(mentionsAny(m, {"data", "size", "bytes", "truncated"})) << m;
}

TEST_F(Malformed, DimensionsThatOverflow32Bits)
{
  // width * point_step does not fit the 32-bit row_step: must be rejected from the header
  // alone, without trying to allocate per-point arrays for 2^32 points
  const Cloud c = small();
  rc::PointCloudView v = c.view();
  v.width = 0x80000000u;
  v.height = 2;
  v.row_step = 0xFFFFFFFFu;
  std::string m = rejectAndRecover(v);
  EXPECT_FALSE(m.empty());

  v.width = 0xFFFFFFFFu;
  v.height = 0xFFFFFFFFu;
  v.row_step = 22;
  m = rejectAndRecover(v);
  EXPECT_FALSE(m.empty());
}

TEST_F(Malformed, OversizedDataIsReadOnlyWithinTheRows)
{
  // data_size is "bytes available": more than the rows need is harmless and ignored
  const Cloud c = small();
  Cloud big = c;
  big.data.resize(c.data.size() + 4096, 0xFF);
  rc::Pipeline a, b;
  rc::FrameResult ra, rb;
  ASSERT_TRUE(a.process(c.view(), ra).ok);
  const rc::Status st = b.process(big.view(), rb);
  ASSERT_TRUE(st.ok) << st.message;
  expectSameResult(ra, rb);
}

TEST_F(Malformed, EmptyFrames)
{
  // width 0 or height 0: either an empty result or a rejection naming the emptiness; never a
  // crash, and the next frame is unaffected
  for (int which = 0; which < 3; ++which)
  {
    Cloud c = small();
    rc::PointCloudView v = c.view();
    if (which == 0) v.width = 0;
    if (which == 1) v.height = 0;
    if (which == 2) v.width = 0, v.height = 0, v.row_step = 0, v.data = nullptr, v.data_size = 0;
    rc::Pipeline pipeline;
    rc::FrameResult r;
    ASSERT_TRUE(pipeline.process(warm_->view(), r).ok);
    const rc::Status st = pipeline.process(v, r);
    if (st.ok)
    {
      expectConsistent(r, 0);
    }
    else
    {
      EXPECT_TRUE(mentionsAny(st.message, {"empty", "width", "height", "no points"})) << st.message;
      rc::test::expectEmpty(r);
    }
    recover(pipeline);
  }
}

TEST_F(Malformed, TooManyOrganizedRows)
{
  // organized without a ring field: row = beam, so 300 rows exceed the default 256 rings
  const int rows = 300, cols = 8;
  std::vector<rc::test::SyntheticPoint> pts(static_cast<std::size_t>(rows) * cols);
  for (std::size_t i = 0; i < pts.size(); ++i)
  {
    pts[i].x = 5.0f;
    pts[i].y = 0.01f * static_cast<float>(i % cols);
    pts[i].z = 0.01f * static_cast<float>(i / cols);
  }
  rc::test::Layout l = rc::test::velodyneLayout();
  l.ring = {};
  const Cloud c = rc::test::pack(pts, l, cols, rows);
  const std::string m = rejectAndRecover(c.view());
  EXPECT_TRUE(mentionsAny(m, {"max_rings", "rows", "height"})) << m;
}

// --- parameters -----------------------------------------------------------------------------

TEST_F(Malformed, InvalidParamsAreRefusedAndTheOldOnesStay)
{
  rc::Pipeline pipeline;
  rc::Params bad;
  bad.max_rings = 0;
  rc::Status st = pipeline.setParams(bad);
  EXPECT_FALSE(st.ok);
  EXPECT_TRUE(mentionsAny(st.message, {"max_rings"})) << st.message;
  bad = {};
  bad.chord_length = std::numeric_limits<float>::quiet_NaN();
  st = pipeline.setParams(bad);
  EXPECT_FALSE(st.ok);
  EXPECT_TRUE(mentionsAny(st.message, {"chord_length"})) << st.message;
  bad = {};
  bad.min_range = 10.0f;
  bad.max_range = 5.0f;
  st = pipeline.setParams(bad);
  EXPECT_FALSE(st.ok);
  EXPECT_TRUE(mentionsAny(st.message, {"min_range", "max_range"})) << st.message;
  EXPECT_EQ(pipeline.params().max_rings, rc::Params().max_rings);
  recover(pipeline);
}

}  // namespace
