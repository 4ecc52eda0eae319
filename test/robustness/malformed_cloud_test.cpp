// Malformed and degenerate clouds through the core (PointCloudView + Pipeline::process).
// For every bad frame: no crash and no out-of-bounds read (the sanitizer build runs this file
// too), a Status whose message names the problem, an empty result, and a pipeline that then
// processes the next good frame exactly as a fresh pipeline would. Degenerate but legal frames
// (one point, all NaN, one ring, shuffled order, 2 million points) must be processed.
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <limits>
#include <numeric>
#include <random>

#include "expectations.hpp"
#include "synthetic_cloud.hpp"

namespace rc = ring_curvature;
using rc::test::Cloud;
using rc::test::expectConsistent;
using rc::test::expectSameResult;
using rc::test::mentionsAny;
using rc::test::mentionsToken;

namespace
{

class Malformed : public ::testing::Test
{
protected:
  static void SetUpTestSuite()
  {
    warm_ = new Cloud(rc::test::goodCloud(16, 900));
    next_ = new Cloud(rc::test::goodCloud(32, 1024));
    next_ref_ = new rc::FrameResult;
    rc::Pipeline fresh;
    const rc::Status st = fresh.process(next_->view(), *next_ref_);
    ASSERT_TRUE(st.ok) << st.message;
  }
  static void TearDownTestSuite()
  {
    delete warm_;
    delete next_;
    delete next_ref_;
  }

  /// Warms a pipeline on a good frame, feeds `bad`, then checks the next good frame.
  /// Returns the rejection message ("" if the frame was wrongly accepted).
  std::string rejectAndRecover(const rc::PointCloudView& bad, const rc::Params& params = {})
  {
    rc::Pipeline pipeline(params);
    rc::FrameResult r;
    rc::Status st = pipeline.process(warm_->view(), r);
    EXPECT_TRUE(st.ok) << st.message;
    st = pipeline.process(bad, r);
    EXPECT_FALSE(st.ok) << "malformed frame accepted";
    EXPECT_FALSE(st.message.empty()) << "rejection without a message";
    rc::test::expectEmpty(r);
    const std::string message = st.ok ? std::string() : st.message;
    std::printf("rejected: %s\n", message.c_str());  // the catalogue docs/robustness.md quotes
    recover(pipeline);
    return message;
  }

  /// The next good frame after anything comes out as from a fresh pipeline.
  void recover(rc::Pipeline& pipeline)
  {
    rc::FrameResult r;
    const rc::Status st = pipeline.process(next_->view(), r);
    ASSERT_TRUE(st.ok) << st.message;
    expectSameResult(r, *next_ref_);
  }

  static Cloud* warm_;
  static Cloud* next_;
  static rc::FrameResult* next_ref_;
};
Cloud* Malformed::warm_ = nullptr;
Cloud* Malformed::next_ = nullptr;
rc::FrameResult* Malformed::next_ref_ = nullptr;

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

// --- degenerate but legal frames --------------------------------------------------------------

void processLegal(const rc::PointCloudView& v, rc::FrameResult& r, const rc::Params& p = {})
{
  rc::Pipeline pipeline(p);
  const rc::Status st = pipeline.process(v, r);
  ASSERT_TRUE(st.ok) << st.message;
  expectConsistent(r, v.size());
}

TEST_F(Malformed, OnePoint)
{
  const Cloud c = rc::test::pack(rc::test::roomScan(1, 1), rc::test::velodyneLayout(), 1, 1);
  rc::FrameResult r;
  processLegal(c.view(), r);
  EXPECT_TRUE(std::isnan(r.curvature[0])) << "curvature of a lone point must be undefined";
  EXPECT_TRUE(r.primitives.primitives.empty());
}

TEST_F(Malformed, AllNaNOrInfinite)
{
  const float vals[] = {std::numeric_limits<float>::quiet_NaN(),
                        std::numeric_limits<float>::infinity(),
                        -std::numeric_limits<float>::infinity()};
  for (float bad : vals)
  {
    auto pts = rc::test::roomScan(16, 360);
    for (auto& p : pts)
      p.x = p.y = p.z = bad;
    const Cloud c = rc::test::pack(pts, rc::test::velodyneLayout(), 16 * 360, 1);
    rc::FrameResult r;
    processLegal(c.view(), r);
    EXPECT_EQ(r.label_counts[0], pts.size()) << "invalid returns must be labelled None";
    EXPECT_TRUE(r.primitives.primitives.empty());
  }
}

TEST_F(Malformed, ExtremeCoordinatesAmongGoodOnes)
{
  // huge, tiny, negative-zero and denormal coordinates: out of range or invalid returns that
  // must not overflow any float-to-integer conversion (UBSan checks this in the sanitizer build)
  auto pts = rc::test::roomScan(16, 360);
  const float extremes[] = {3e38f, -3e38f, 1e-38f, 1e-45f, -0.0f, 1e20f, 249.9f, 250.1f};
  for (std::size_t i = 0; i < pts.size(); i += 37)
  {
    const float e = extremes[(i / 37) % 8];
    pts[i].x = e;
    pts[i].y = (i % 2) ? e : -e;
  }
  const Cloud c = rc::test::pack(pts, rc::test::velodyneLayout(), 16 * 360, 1);
  rc::FrameResult r;
  processLegal(c.view(), r);
  EXPECT_EQ(r.label[0], 0) << "a 3e38 m return is out of range";
}

TEST_F(Malformed, AllPointsIdentical)
{
  for (bool same_ring : {true, false})
  {
    auto pts = rc::test::roomScan(16, 360);
    for (auto& p : pts)
    {
      p.x = 3.0f, p.y = 1.0f, p.z = 0.5f;
      if (same_ring) p.ring = 5;
    }
    const Cloud c = rc::test::pack(pts, rc::test::velodyneLayout(), 16 * 360, 1);
    rc::FrameResult r;
    processLegal(c.view(), r);
    // one position in space is one sample: nothing can bend there
    for (float k : r.curvature)
      EXPECT_TRUE(std::isnan(k) || k == 0.0f) << k;
  }
}

TEST_F(Malformed, AllPointsAtTheOrigin)
{
  auto pts = rc::test::roomScan(16, 360);
  for (auto& p : pts)
    p.x = p.y = p.z = 0.0f;
  const Cloud c = rc::test::pack(pts, rc::test::velodyneLayout(), 16 * 360, 1);
  rc::FrameResult r;
  processLegal(c.view(), r);
  EXPECT_EQ(r.label_counts[0], pts.size()) << "zero range is below min_range";
}

TEST_F(Malformed, SingleRing)
{
  const Cloud c = rc::test::pack(rc::test::roomScan(1, 1800), rc::test::velodyneLayout(), 1800, 1);
  rc::FrameResult r;
  processLegal(c.view(), r);
  // a horizontal ring in a box room sees walls almost everywhere
  EXPECT_GT(r.label_counts[static_cast<int>(rc::Label::Plane)], 1800u / 2);
}

TEST_F(Malformed, SparseRingIndices)
{
  // rings 0 and 200 only: the 199 empty rings between them must not break anything
  auto pts = rc::test::roomScan(2, 900);
  for (auto& p : pts)
    if (p.ring == 1) p.ring = 200;
  const Cloud c = rc::test::pack(pts, rc::test::velodyneLayout(), 2 * 900, 1);
  rc::FrameResult r;
  processLegal(c.view(), r);
  EXPECT_GT(r.label_counts[static_cast<int>(rc::Label::Plane)], 0u);
}

/// Runs `pts` and a permutation of it; per-point results must follow the points.
void expectOrderIndependent(const std::vector<rc::test::SyntheticPoint>& pts,
                            const std::vector<std::size_t>& perm)
{
  std::vector<rc::test::SyntheticPoint> shuffled(pts.size());
  for (std::size_t i = 0; i < perm.size(); ++i)
    shuffled[i] = pts[perm[i]];
  const auto n = static_cast<std::uint32_t>(pts.size());
  const Cloud a = rc::test::pack(pts, rc::test::velodyneLayout(), n, 1);
  const Cloud b = rc::test::pack(shuffled, rc::test::velodyneLayout(), n, 1);
  rc::FrameResult ra, rb;
  processLegal(a.view(), ra);
  processLegal(b.view(), rb);
  std::size_t label_diffs = 0, curv_diffs = 0;
  for (std::size_t i = 0; i < perm.size(); ++i)
  {
    label_diffs += ra.label[perm[i]] != rb.label[i];
    curv_diffs += !rc::test::sameFloat(ra.curvature[perm[i]], rb.curvature[i]);
  }
  EXPECT_EQ(label_diffs, 0u);
  EXPECT_EQ(curv_diffs, 0u);
  EXPECT_EQ(ra.primitives.primitives.size(), rb.primitives.primitives.size());
}

TEST_F(Malformed, AzimuthsNotMonotonic)
{
  const auto pts = rc::test::roomScan(16, 900);
  std::vector<std::size_t> perm(pts.size());
  std::iota(perm.begin(), perm.end(), 0);
  std::reverse(perm.begin(), perm.end());  // a sensor spinning the other way
  expectOrderIndependent(pts, perm);
  std::mt19937 rng(7);
  std::shuffle(perm.begin(), perm.end(), rng);  // no order at all
  expectOrderIndependent(pts, perm);
}

TEST_F(Malformed, TwoMillionPoints)
{
  const int rings = 128, samples = 15625;  // 2,000,000 points
  const Cloud c = rc::test::pack(rc::test::roomScan(rings, samples), rc::test::velodyneLayout(),
                                 rings * samples, 1);
  rc::Pipeline pipeline;
  rc::FrameResult r;
  const auto t0 = std::chrono::steady_clock::now();
  const rc::Status st = pipeline.process(c.view(), r);
  const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  ASSERT_TRUE(st.ok) << st.message;
  expectConsistent(r, c.size());
  EXPECT_GT(r.label_counts[static_cast<int>(rc::Label::Plane)], c.size() / 2);
  std::printf("2,000,000 points: %.2f s\n", s);
  recover(pipeline);
}

// --- equivalent layouts give equal results ----------------------------------------------------

TEST_F(Malformed, LayoutsAndTypesDoNotChangeTheResult)
{
  const auto pts = rc::test::roomScan(16, 900);
  const std::uint32_t n = 16 * 900;
  rc::FrameResult ref;
  processLegal(rc::test::pack(pts, rc::test::velodyneLayout(), n, 1).view(), ref);

  std::vector<rc::test::Layout> layouts;
  layouts.push_back(rc::test::ousterLayout());
  for (rc::ScalarType t : {rc::ScalarType::UInt8, rc::ScalarType::Int16, rc::ScalarType::Int32,
                           rc::ScalarType::UInt32})
  {
    rc::test::Layout l = rc::test::ousterLayout();
    l.ring = {32, t};
    layouts.push_back(l);
  }
  rc::test::Layout wide = rc::test::ousterLayout();  // float64 coordinates
  wide.x = {0, rc::ScalarType::Float64};
  wide.y = {8, rc::ScalarType::Float64};
  wide.z = {28, rc::ScalarType::Float64};
  wide.ring = {36, rc::ScalarType::UInt16};
  layouts.push_back(wide);
  for (const auto& l : layouts)
  {
    rc::FrameResult r;
    processLegal(rc::test::pack(pts, l, n, 1).view(), r);
    expectSameResult(r, ref);
  }
}

TEST_F(Malformed, RowPaddingIsSkipped)
{
  // row_step > width * point_step is legal; the padding (0xA5 garbage) must never be read
  const auto pts = rc::test::toOrganized(rc::test::roomScan(16, 900), 16, 900);
  rc::FrameResult a, b;
  processLegal(rc::test::pack(pts, rc::test::velodyneLayout(), 900, 16).view(), a);
  processLegal(rc::test::pack(pts, rc::test::velodyneLayout(), 900, 16, 13).view(), b);
  expectSameResult(a, b);
}

TEST_F(Malformed, ChangingFrameSizesLeaveNoStaleState)
{
  rc::Pipeline pipeline;
  rc::FrameResult r;
  for (int rings : {128, 1, 64, 16})
  {
    const Cloud c = rc::test::goodCloud(rings, 2000);
    ASSERT_TRUE(pipeline.process(c.view(), r).ok);
    expectConsistent(r, c.size());
  }
  recover(pipeline);
}

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
