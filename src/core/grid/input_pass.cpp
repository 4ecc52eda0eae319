// The grid's input pass: every input record read once into per-point scratch (range, validity,
// ring, azimuth), with fast paths for the common layouts, and rings found from elevation when a
// cloud has no ring field.
#include "ring_curvature/scan_grid.hpp"
#include "grid/scan_grid_builder.hpp"
#include "common/float_bits.hpp"

#include "common/angles.hpp"
#include "grid/record_read.hpp"
#include "common/simd_clones.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <sstream>

namespace ring_curvature
{

namespace
{

// Point i's entries: its range decides validity (NaN and inf fail both comparisons); invalid
// points' are written too. Float32 x, y, z feed the azimuths and, for float32 clouds, the grid.
struct PointEntries
{
  double* range;
  float* x;
  float* y;
  float* z;
  std::int32_t* ring;
  PointState* state;
  std::int32_t* grid_pos;
};
inline void storePoint(const PointEntries& out, std::size_t i, double x, double y, double z, std::int32_t ring,
                       double rmin, double rmax)
{
  const double range = std::sqrt(x * x + y * y + z * z);
  const bool valid = (range >= rmin) & (range <= rmax);
  out.range[i] = range;
  out.x[i] = static_cast<float>(x);
  out.y[i] = static_cast<float>(y);
  out.z[i] = static_cast<float>(z);
  out.ring[i] = valid ? ring : -1;
  out.state[i] = valid ? PointState::OnGrid : PointState::Invalid;
  out.grid_pos[i] = -1;
}

// The common layout: float32 x, y, z at fixed offsets and a uint16 ring field. No branches or
// early exits, so it vectorizes: returns the largest ring read, for the caller to reject the frame
// after the loop.
RC_SIMD_CLONES std::uint32_t readXyzRecords(const std::uint8_t* __restrict data, std::size_t n, std::size_t step,
                                            std::size_t ox, std::size_t oy, std::size_t oz, std::size_t oring,
                                            double rmin, double rmax, double* __restrict range_out,
                                            float* __restrict px, float* __restrict py, float* __restrict pz,
                                            std::int32_t* __restrict ring_out, PointState* __restrict state,
                                            std::int32_t* __restrict grid_pos)
{
  const PointEntries out{range_out, px, py, pz, ring_out, state, grid_pos};
  std::uint32_t max_read = 0;
  for (std::size_t i = 0; i < n; ++i)
  {
    const std::uint8_t* const rec = data + i * step;
    const float fx = readFloat32(rec + ox), fy = readFloat32(rec + oy), fz = readFloat32(rec + oz);
    std::uint16_t r16;
    std::memcpy(&r16, rec + oring, sizeof r16);
    max_read = std::max<std::uint32_t>(max_read, r16);
    storePoint(out, i, fx, fy, fz, static_cast<std::int32_t>(r16), rmin, rmax);
  }
  return max_read;
}

// Azimuths of points at once (fastAtan2 is branch-free: 4 or 8 at a time).
RC_SIMD_CLONES void azimuths(std::size_t n, const float* __restrict x, const float* __restrict y,
                             float* __restrict azimuth)
{
  for (std::size_t i = 0; i < n; ++i) azimuth[i] = fastAtan2(y[i], x[i]);
}

// The error for point i whose ring field holds r, outside [0, max_rings).
Status ringOutOfRange(std::size_t i, std::int64_t r, const Params& params)
{
  std::ostringstream s;
  s << "point " << i << " has ring " << r << ", outside [0, max_rings = " << params.max_rings << ")";
  return Status::error(s.str());
}
}  // namespace

Status ScanGridBuilder::readPoints(const PointCloudView& view, const Params& params, ScanGrid& grid)
{
  const std::size_t n = view.size();
  grid.num_input = n;
  placed_ = false;
  // Every entry of these is written below (no fill first: one pass over the frame instead of two).
  grid.state.resize(n);
  grid.grid_pos.resize(n);
  ring_of_.resize(n);
  prange_.resize(n + 1);  // [n]: the ring fold's sentinel range (ring_sort.cpp)
  paz_.resize(n);
  px_.resize(n);
  py_.resize(n);
  pz_.resize(n);
  const double rmin = params.min_range, rmax = params.max_range;
  const auto ringError = [&](std::size_t i, std::int64_t r) { return ringOutOfRange(i, r, params); };
  // The first point whose uint16 ring field is max_rings or more (one is known to be), for the
  // message: the fast input pass only tracks the largest value read.
  const auto firstRing16Error = [&]() {
    std::size_t i = 0;
    std::uint16_t r16 = 0;
    for (; i < n; ++i)
    {
      std::memcpy(&r16, view.record(i) + view.ring.offset, sizeof r16);
      if (r16 >= params.max_rings) break;
    }
    return ringError(i, r16);
  };
  const bool fast = view.x.type == ScalarType::Float32 && view.y.type == ScalarType::Float32 &&
                    view.z.type == ScalarType::Float32;
  if (fast && view.organized())
  {
    std::uint32_t largest = 0;
    if (readOrganized(view, params, grid, largest))
    {
      if (largest >= static_cast<std::uint32_t>(params.max_rings)) return firstRing16Error();
      placed_ = true;
      grid.num_rings = static_cast<int>(view.height);
      return Status::success();
    }
  }
  if (fast && !view.organized() && view.ring.present() && view.ring.type == ScalarType::UInt16)
  {
    const std::uint32_t max_read = readXyzRecords(
        view.data, n, view.point_step, static_cast<std::size_t>(view.x.offset), static_cast<std::size_t>(view.y.offset),
        static_cast<std::size_t>(view.z.offset), static_cast<std::size_t>(view.ring.offset), rmin, rmax, prange_.data(),
        px_.data(), py_.data(), pz_.data(), ring_of_.data(), grid.state.data(), grid.grid_pos.data());
    azimuths(n, px_.data(), py_.data(), paz_.data());
    if (max_read >= static_cast<std::uint32_t>(params.max_rings)) return firstRing16Error();
  }
  else
  {
    const PointEntries entries{prange_.data(), px_.data(), py_.data(), pz_.data(),
                               ring_of_.data(), grid.state.data(), grid.grid_pos.data()};
    for (std::uint32_t row = 0; row < view.height; ++row)
    {
      const std::uint8_t* rec = view.data + static_cast<std::size_t>(row) * view.row_step;
      for (std::uint32_t col = 0; col < view.width; ++col, rec += view.point_step)
      {
        const std::size_t i = static_cast<std::size_t>(row) * view.width + col;
        int ring = static_cast<int>(row);
        if (view.ring.present())
        {
          const std::int64_t r = readInteger(rec + view.ring.offset, view.ring.type);
          if (r < 0 || r >= params.max_rings) return ringError(i, r);
          if (!view.organized()) ring = static_cast<int>(r);  // organized: the row is the ring
        }
        storePoint(entries, i, readCoord(rec, view.x), readCoord(rec, view.y), readCoord(rec, view.z), ring, rmin,
                   rmax);
      }
    }
    azimuths(n, px_.data(), py_.data(), paz_.data());
  }
  countRings(n, params);
  int max_ring = -1;
  for (int r = params.max_rings - 1; r >= 0 && max_ring < 0; --r)
    if (ring_count_[static_cast<std::size_t>(r) + 1] > 0) max_ring = r;
  grid.num_rings = view.organized() ? static_cast<int>(view.height) : max_ring + 1;
  return Status::success();
}

// Points per ring ([0]: invalid ones), for the counting sort, in a pass of its own: the
// increments would keep the input loops from vectorizing.
void ScanGridBuilder::countRings(std::size_t n, const Params& params)
{
  // Four interleaved tallies, summed after: rings that arrive one after another (KITTI's, an
  // organized cloud's) would otherwise chain every increment to the store of the one before.
  const std::size_t slots = static_cast<std::size_t>(params.max_rings) + 1;
  ring_count_.assign(4 * slots, 0);
  std::uint32_t* const count = ring_count_.data() + 1;  // ring -1 (invalid) counts at [0]
  const std::int32_t* const ring = ring_of_.data();
  std::size_t i = 0;
  for (; i + 4 <= n; i += 4)
  {
    ++count[ring[i]];
    ++count[slots + static_cast<std::size_t>(ring[i + 1])];
    ++count[2 * slots + static_cast<std::size_t>(ring[i + 2])];
    ++count[3 * slots + static_cast<std::size_t>(ring[i + 3])];
  }
  for (; i < n; ++i) ++count[ring[i]];
  for (std::size_t r = 0; r < slots; ++r)
    ring_count_[r] += ring_count_[slots + r] + ring_count_[2 * slots + r] + ring_count_[3 * slots + r];
}

void ScanGridBuilder::assignRingsFromElevation(const PointCloudView& view, const Params& params, ScanGrid& grid)
{
  // Histogram of elevation at 0.05 deg; runs of occupied bins (a beam's spread) become rings,
  // numbered from the lowest elevation up (the velodyne convention).
  constexpr int kBins = 3600;
  constexpr float kBinRad = kPi / kBins;
  const std::size_t n = grid.num_input;
  counts_.assign(kBins, 0);
  tmp_f_.resize(n);
  for (std::size_t i = 0; i < n; ++i)
  {
    if (ring_of_[i] < 0) continue;
    const std::uint8_t* rec = view.record(i);  // unorganized here: no per-point division cost
    const double x = readCoord(rec, view.x), y = readCoord(rec, view.y), z = readCoord(rec, view.z);
    const float horiz = static_cast<float>(std::sqrt(x * x + y * y));
    const float el = fastAtan2(static_cast<float>(z), horiz);
    tmp_f_[i] = el;
    const int b = std::clamp(static_cast<int>((el + kPi / 2) / kBinRad), 0, kBins - 1);
    ++counts_[static_cast<std::size_t>(b)];
  }
  bin_start_.assign(kBins, 0);  // ring id of each bin
  int ring = -1;
  int last_occupied = -10;
  for (int b = 0; b < kBins; ++b)
  {
    if (counts_[static_cast<std::size_t>(b)] == 0) continue;
    if (b - last_occupied > 2) ++ring;  // a gap of two empty bins (0.1 deg) separates beams
    last_occupied = b;
    bin_start_[static_cast<std::size_t>(b)] = static_cast<std::uint32_t>(ring);
  }
  const int num = std::min(ring + 1, params.max_rings);
  std::fill(ring_count_.begin() + 1, ring_count_.end(), 0u);  // recounted for the new rings
  for (std::size_t i = 0; i < n; ++i)
  {
    if (ring_of_[i] < 0) continue;
    const int b = std::clamp(static_cast<int>((tmp_f_[i] + kPi / 2) / kBinRad), 0, kBins - 1);
    ring_of_[i] = std::min(static_cast<int>(bin_start_[static_cast<std::size_t>(b)]), num - 1);
    ++ring_count_[static_cast<std::size_t>(ring_of_[i]) + 1];
  }
  grid.num_rings = std::max(num, 0);
}

}  // namespace ring_curvature
