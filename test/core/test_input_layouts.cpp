// The float32 input pass (grid_input.cpp's readRecords, unorganized and row by row organized)
// over record layouts other than the shipped bags': record steps 14 to 48, x not at 0, the ring
// before, right after z, ending the record or across two 4-byte words, y and z not following x,
// frame sizes around the groups of 8 and 16 (the vectorized loop's), rings in turn and one after
// another, organized rows with and without a ring field and with row padding.
// Each frame is compared bit for bit with the same values in float64 records, which take the
// generic input pass, and is read from a buffer that ends where an inaccessible page begins, so
// that a read past the end of the data faults.
#include <gtest/gtest.h>

#include <sys/mman.h>
#include <unistd.h>

#include <cmath>
#include <cstring>
#include <limits>
#include <memory>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

#include "../support/same_bits.hpp"
#include "../support/synthetic_cloud.hpp"
#include "ring_curvature/pipeline.hpp"

using namespace ring_curvature;
using namespace ring_curvature::test;

namespace
{
// `size` bytes that end at the first byte of a page nothing may read.
class GuardedBuffer
{
public:
  explicit GuardedBuffer(std::size_t size)
  {
    const auto page = static_cast<std::size_t>(sysconf(_SC_PAGESIZE));
    length_ = (size + page - 1) / page * page + page;
    void* m = mmap(nullptr, length_, PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS, -1, 0);
    if (m == MAP_FAILED) throw std::runtime_error("mmap failed");
    base_ = static_cast<std::uint8_t*>(m);
    if (mprotect(base_ + length_ - page, page, PROT_NONE) != 0) throw std::runtime_error("mprotect failed");
    data_ = base_ + length_ - page - size;
  }
  ~GuardedBuffer() { munmap(base_, length_); }
  GuardedBuffer(const GuardedBuffer&) = delete;
  GuardedBuffer& operator=(const GuardedBuffer&) = delete;
  std::uint8_t* data() const { return data_; }

private:
  std::uint8_t* base_ = nullptr;
  std::uint8_t* data_ = nullptr;
  std::size_t length_ = 0;
};

struct Layout
{
  std::uint32_t step;
  std::int64_t ox, oy, oz, oring;  // oring -1: none
  std::uint32_t row_pad = 0;       // organized: bytes after each row's records
};
std::string name(const Layout& L)
{
  return "step " + std::to_string(L.step) + " x/y/z/ring at " + std::to_string(L.ox) + "/" + std::to_string(L.oy) +
         "/" + std::to_string(L.oz) + "/" + std::to_string(L.oring) + " row pad " + std::to_string(L.row_pad);
}

struct Point
{
  float x, y, z;
  int ring;
};

// A scan of n points, rings 0..15 in turn (a velodyne's firings), azimuth increasing, with NaN
// padding, infinities, returns below the minimum range and signed zeros among them. With
// ring_after_ring, the rings come one after another instead, each in azimuth order (KITTI's
// layout: the grid's index then holds long runs of consecutive input points).
std::vector<Point> scanPoints(std::size_t n, unsigned seed, bool ring_after_ring = false)
{
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  std::vector<Point> pts;
  const std::size_t per_ring = (n + 15) / 16;
  for (std::size_t k = 0; k < n; ++k)
  {
    const int ring = static_cast<int>(ring_after_ring ? k / per_ring : k % 16);
    const double t = ring_after_ring ? static_cast<double>(k % per_ring) / static_cast<double>(per_ring)
                                     : static_cast<double>(k) / static_cast<double>(n);
    const double az = -3.0 + 6.0 * t, el = -0.25 + 0.03 * ring;
    const double r = k % (ring_after_ring ? 110 : 11) == 5 ? 0.05 : 2.0 + 30.0 * u(rng);
    Point p{static_cast<float>(r * std::cos(el) * std::cos(az)), static_cast<float>(r * std::cos(el) * std::sin(az)),
            static_cast<float>(r * std::sin(el)), ring};
    // (ring after ring: the invalid returns sparser, so that long stretches of valid ones occur)
    const std::size_t every = ring_after_ring ? 10 : 1;
    if (k % (7 * every) == 3) p.x = p.y = p.z = std::numeric_limits<float>::quiet_NaN();
    if (k % (19 * every) == 4) p.z = std::numeric_limits<float>::infinity();
    if (k % 13 == 0) p.y = -0.0f;
    if (k % 17 == 0) p.x = 0.0f;
    pts.push_back(p);
  }
  return pts;
}

// pts in records of layout L in a guarded buffer, as `height` rows (1: unorganized). The bytes
// no field covers are 0xff, so that a ring read not narrowed to 16 bits is out of range.
PointCloudView writeRecords(const std::vector<Point>& pts, const Layout& L, std::uint32_t height,
                            std::unique_ptr<GuardedBuffer>& buf)
{
  const std::size_t width = pts.size() / height, row_step = width * L.step + (height > 1 ? L.row_pad : 0);
  const std::size_t size = (height - 1) * row_step + width * L.step;
  buf = std::make_unique<GuardedBuffer>(size);
  std::memset(buf->data(), 0xff, size);
  for (std::size_t i = 0; i < pts.size(); ++i)
  {
    std::uint8_t* rec = buf->data() + (i / width) * row_step + (i % width) * L.step;
    std::memcpy(rec + L.ox, &pts[i].x, 4);
    std::memcpy(rec + L.oy, &pts[i].y, 4);
    std::memcpy(rec + L.oz, &pts[i].z, 4);
    const auto r16 = static_cast<std::uint16_t>(pts[i].ring);
    if (L.oring >= 0) std::memcpy(rec + L.oring, &r16, 2);
  }
  PointCloudView v;
  v.data = buf->data();
  v.data_size = size;
  v.height = height;
  v.width = static_cast<std::uint32_t>(width);
  v.point_step = L.step;
  v.row_step = static_cast<std::uint32_t>(row_step);
  v.x = {L.ox, ScalarType::Float32};
  v.y = {L.oy, ScalarType::Float32};
  v.z = {L.oz, ScalarType::Float32};
  if (L.oring >= 0) v.ring = {L.oring, ScalarType::UInt16};
  return v;
}

// The same values in float64 records (the generic input pass).
SyntheticCloud reference(const std::vector<Point>& pts)
{
  SyntheticCloud c(true);
  for (const Point& p : pts) c.add(p.x, p.y, p.z, p.ring);
  return c;
}

void expectSameGrid(const Pipeline& fast, const FrameResult& rf, const Pipeline& generic, const FrameResult& rg,
                    const std::string& what)
{
  const ScanGrid &a = fast.grid(), &b = generic.grid();
  EXPECT_GT(a.size(), 0u) << what;
  EXPECT_EQ(a.num_rings, b.num_rings) << what;
  EXPECT_EQ(a.num_valid, b.num_valid) << what;
  EXPECT_TRUE(sameBits(a.ring_begin, b.ring_begin)) << what;
  EXPECT_TRUE(sameBits(a.ring_elevation, b.ring_elevation)) << what;
  EXPECT_TRUE(sameBits(a.index, b.index)) << what;
  EXPECT_TRUE(sameBits(a.azimuth, b.azimuth)) << what;
  EXPECT_TRUE(sameBits(a.x, b.x)) << what;
  EXPECT_TRUE(sameBits(a.y, b.y)) << what;
  EXPECT_TRUE(sameBits(a.z, b.z)) << what;
  EXPECT_TRUE(sameBits(a.range, b.range)) << what;
  EXPECT_TRUE(sameBits(a.state, b.state)) << what;
  EXPECT_TRUE(sameBits(a.grid_pos, b.grid_pos)) << what;
  EXPECT_TRUE(sameBits(rf.label, rg.label)) << what;
  EXPECT_TRUE(sameBits(rf.curvature, rg.curvature)) << what;
}

// x, y, z one run of floats and not; the ring anywhere around them.
const Layout kLayouts[] = {
    {22, 0, 4, 8, 16},   // velodyne XYZIRT, packed
    {14, 0, 4, 8, 12},   // ring right after z, records not 4-byte aligned
    {16, 4, 8, 12, 0},   // ring first, z ends the record
    {16, 0, 4, 8, 12},   //
    {32, 0, 4, 8, 16},   // PCL-padded
    {48, 0, 4, 8, 26},   // ouster
    {48, 20, 24, 28, 2},  // x late in the record
    {18, 0, 4, 8, 16},   // the ring ends the record
    {28, 8, 12, 16, 26},  // the ring in the high half of its word, ending the record
    {32, 0, 4, 8, 30},   // ... the last two bytes of the 32 from x
    {24, 0, 4, 8, 19},   // across two words
    {16, 0, 8, 4, 12},   // z before y
    {24, 12, 4, 20, 0},  // scattered
};

// pts as one unorganized frame of layout L, through the float32 passes, against the generic pass.
void expectUnorganizedMatches(const std::vector<Point>& pts, const Layout& L, const std::string& what)
{
  std::unique_ptr<GuardedBuffer> buf;
  const PointCloudView v = writeRecords(pts, L, 1, buf);
  const SyntheticCloud ref = reference(pts);
  Pipeline fast, generic;
  FrameResult rf, rg;
  ASSERT_TRUE(fast.process(v, rf).ok) << what;
  ASSERT_TRUE(generic.process(ref.view(), rg).ok) << what;
  expectSameGrid(fast, rf, generic, rg, what);
}
}  // namespace

// Unorganized frames with a ring field: sizes below, at and around multiples of 8 and 16.
TEST(InputLayouts, UnorganizedMatchesTheGenericPass)
{
  for (const Layout& L : kLayouts)
    for (const std::size_t n : {5u, 8u, 9u, 16u, 17u, 23u, 24u, 25u, 33u, 1003u, 4096u})
      expectUnorganizedMatches(scanPoints(n, static_cast<unsigned>(n + L.step)), L,
                               name(L) + ", " + std::to_string(n) + " points");
}

// Rings one after another (the grid's index then holds runs of consecutive input points),
// around the groups of eight.
TEST(InputLayouts, RingAfterRingMatchesTheGenericPass)
{
  for (const Layout& L : {kLayouts[0], kLayouts[4], kLayouts[11]})
    for (const std::size_t n : {9u, 16u, 17u, 130u, 1003u, 4096u})
      expectUnorganizedMatches(scanPoints(n, static_cast<unsigned>(2 * n + L.step), true), L,
                               name(L) + ", " + std::to_string(n) + " points ring after ring");
}

// A ring field of max_rings or more in any lane of a group (or in the points read one at a
// time) is found by the largest value read, and named.
TEST(InputLayouts, RingOutOfRangeInEveryLane)
{
  Params params;
  params.max_rings = 16;
  for (const Layout& L : {kLayouts[0], kLayouts[1], kLayouts[2], kLayouts[5], kLayouts[8]})
    for (std::size_t bad = 0; bad < 41; ++bad)
    {
      std::vector<Point> pts = scanPoints(41, 9);
      pts[bad].ring = 16 + static_cast<int>(bad);
      std::unique_ptr<GuardedBuffer> buf;
      Pipeline p(params);
      FrameResult r;
      const Status st = p.process(writeRecords(pts, L, 1, buf), r);
      ASSERT_FALSE(st.ok) << name(L) << ", point " << bad;
      EXPECT_NE(st.message.find("point " + std::to_string(bad) + " has ring " + std::to_string(16 + bad)),
                std::string::npos)
          << name(L) << ": " << st.message;
    }
}

// Organized frames (the row is the ring): widths below, at and around multiples of 8 and 16,
// with and without a ring field, with and without padding after each row.
TEST(InputLayouts, OrganizedMatchesTheGenericPass)
{
  const int rows = 6;
  std::vector<Layout> layouts(std::begin(kLayouts), std::end(kLayouts));
  layouts.push_back({22, 0, 4, 8, -1});
  layouts.push_back({16, 4, 8, 12, -1});
  layouts.push_back({14, 0, 4, 8, 12, 6});
  layouts.push_back({16, 4, 8, 12, -1, 2});
  for (const Layout& L : layouts)
    for (const std::size_t width : {5u, 8u, 9u, 16u, 17u, 24u, 31u, 203u})
    {
      std::vector<Point> pts = scanPoints(rows * width, static_cast<unsigned>(width + L.step));
      for (std::size_t i = 0; i < pts.size(); ++i) pts[i].ring = rows - 1 - static_cast<int>(i / width);
      std::unique_ptr<GuardedBuffer> buf;
      const PointCloudView v = writeRecords(pts, L, rows, buf);
      const SyntheticCloud ref = reference(pts);
      Pipeline fast, generic;
      FrameResult rf, rg;
      const std::string what = name(L) + ", width " + std::to_string(width);
      ASSERT_TRUE(fast.process(v, rf).ok) << what;
      ASSERT_TRUE(generic.process(ref.view(rows), rg).ok) << what;
      ASSERT_TRUE(fast.grid().organized) << what;
      expectSameGrid(fast, rf, generic, rg, what);
    }
}
