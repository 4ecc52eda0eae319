#include "loam/loam_selector.hpp"

#include "common/angles.hpp"
#include "common/ring_index.hpp"
#include "loam/degeneracy.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>

namespace ring_curvature
{

namespace
{
constexpr std::uint8_t kExcluded = 1;    // occluded or along the beam: in no set
constexpr std::uint8_t kSuppressed = 2;  // next to a chosen point: not chosen itself
constexpr std::uint64_t kNoKey = ~std::uint64_t{0};

std::uint64_t voxelKey(double x, double y, double z, double inv)
{
  // 21 bits per axis: +-1e6 voxels, i.e. +-200 km at 0.2 m, beyond any LiDAR's range. The floor
  // by truncation: std::floor is a library call on baseline x86-64, once per axis and point.
  const auto axis = [inv](double v) {
    const double t = std::min(std::max(v * inv, -1048576.0), 1048575.0);
    auto c = static_cast<std::int64_t>(t);
    if (static_cast<double>(c) > t) --c;
    return static_cast<std::uint64_t>(c + 1048576);
  };
  return axis(x) << 42 | axis(y) << 21 | axis(z);
}

/// A candidate as one integer that orders as LOAM does (the sharpest, or the flattest, first;
/// then by position): the bits of a non-negative float order as the float, and integer keys
/// are several times faster to select and sort than a score-and-position pair.
std::uint64_t candidateKey(float turn, bool sharpest_first, std::uint32_t pos)
{
  const float a = std::fabs(turn);
  std::uint32_t bits;
  std::memcpy(&bits, &a, sizeof bits);
  return static_cast<std::uint64_t>(sharpest_first ? ~bits : bits) << 32 | pos;
}

/// Each grid point's time field (read(record) gives it), by grid position, and their range
/// (lo, hi). In input order: the records are read as they lie, not scattered in grid order.
template <typename Read>
void readTimes(const PointCloudView& view, const ScanGrid& grid, Read read, std::vector<double>& out, double& lo, double& hi)
{
  for (std::size_t i = 0; i < grid.num_input; ++i)
  {
    if (grid.state[i] != PointState::OnGrid) continue;
    const double t = read(view.record(i) + view.time.offset);
    out[static_cast<std::size_t>(grid.grid_pos[i])] = t;
    lo = std::min(lo, t);
    hi = std::max(hi, t);
  }
}

template <typename T>
double load(const std::uint8_t* p)
{
  T v;
  std::memcpy(&v, p, sizeof v);  // (records may be packed)
  return static_cast<double>(v);
}
}  // namespace

void LoamSelector::select(const PointCloudView& view, const ScanGrid& grid, const Features& f,
                          const std::vector<Label>& labels, const Params& params, LoamFeatures& out)
{
  out.sharp.clear();
  out.less_sharp.clear();
  out.flat.clear();
  out.less_flat.clear();
  exclusions(grid, params);
  sweepTimes(view, grid, params, out);

  const int sectors = params.loam_sectors;
  for (int n = 0; n < grid.num_rings; ++n)
  {
    const RingSpan s(grid, n);
    for (int sec = 0; sec < sectors; ++sec)
    {
      const std::uint32_t lo = s.b + static_cast<std::uint32_t>(static_cast<std::uint64_t>(s.K) * sec / sectors);
      const std::uint32_t hi = s.b + static_cast<std::uint32_t>(static_cast<std::uint64_t>(s.K) * (sec + 1) / sectors);
      // LOAM's order: the sharp points first, then the flat ones among what they left free.
      sharp_.clear();
      for (std::uint32_t p = lo; p < hi; ++p)
      {
        const Label l = labels[p];
        const float turn = f.turning[p];
        if ((l == Label::Edge || l == Label::Corner) && !blocked_[p] && std::isfinite(turn))
          sharp_.push_back(candidateKey(turn, true, p));
      }
      pick(grid, s, sharp_, params.loam_less_sharp_per_sector, params.loam_suppression, out.less_sharp, &out.sharp,
           params.loam_sharp_per_sector);
      roughJumps(lo, hi, f, labels, params.loam_rough_jump, out.less_sharp);
      flat_.clear();
      for (std::uint32_t p = lo; p < hi; ++p)
      {
        const float turn = f.turning[p];
        if (labels[p] == Label::Plane && !blocked_[p] && std::isfinite(turn)) flat_.push_back(candidateKey(turn, false, p));
      }
      pick(grid, s, flat_, params.loam_flat_per_sector, params.loam_suppression, out.flat, nullptr, 0);
    }
    lessFlat(grid, s.b, s.K, labels, params, out);
  }
  out.degeneracy = assessDegeneracy(grid, labels, out, params);
}

void LoamSelector::roughJumps(std::uint32_t lo, std::uint32_t hi, const Features& f, const std::vector<Label>& labels,
                              float min_jump, std::vector<std::uint32_t>& out)
{
  // No exclusions here: nearly every jump sample of foliage steps steeply to both neighbours (the
  // grazing test), and the map's line fit keeps only the ones that line up over scans.
  if (min_jump <= 0.0f) return;
  for (std::uint32_t p = lo; p < hi; ++p)
    if (labels[p] == Label::Rough && f.discontinuity[p] > min_jump) out.push_back(p);
}

void LoamSelector::exclusions(const ScanGrid& grid, const Params& params)
{
  blocked_.assign(grid.size(), 0);
  const double occl = params.loam_occlusion_ratio, par = params.loam_parallel_ratio;
  const int shadow = params.loam_suppression + 1;  // LOAM drops the far side's six samples
  for (int n = 0; n < grid.num_rings; ++n)
  {
    const RingSpan s(grid, n);
    const RingLinks links{grid, s};
    for (std::uint32_t k = 0; k < s.K; ++k)
    {
      const std::uint32_t p = s.b + k;
      const std::int64_t q = links.prev(k), nx = links.next(k);
      const double r1 = grid.range[p];
      // Grazing surface: its points move with the beam, not with the scene. Steep range steps
      // to both neighbours, or to the one there is at a gap (where a grazing wall fades out).
      const bool steep_behind = q >= 0 && std::fabs(r1 - grid.range[static_cast<std::size_t>(q)]) > par * r1;
      const bool steep_ahead = nx >= 0 && std::fabs(grid.range[static_cast<std::size_t>(nx)] - r1) > par * r1;
      if ((steep_behind || q < 0) && (steep_ahead || nx < 0) && (q >= 0 || nx >= 0))
        blocked_[p] |= kExcluded;
      if (q < 0) continue;
      const double r0 = grid.range[static_cast<std::size_t>(q)];
      if (std::fabs(r1 - r0) > occl * std::min(r0, r1))
      {
        // Walk from the jump into the far side: that surface continues behind the near one, so
        // its samples next to the jump are where the occluder's edge happens to cut it.
        const bool forward = r1 > r0;
        std::int64_t at = forward ? static_cast<std::int64_t>(p) : q;
        std::uint32_t local = forward ? k : static_cast<std::uint32_t>(at - s.b);
        for (int i = 0; i < shadow && at >= 0; ++i)
        {
          blocked_[static_cast<std::size_t>(at)] |= kExcluded;
          at = forward ? links.next(local) : links.prev(local);
          if (at >= 0) local = static_cast<std::uint32_t>(at - s.b);
        }
      }
    }
  }
}

void LoamSelector::block(const ScanGrid& grid, const RingSpan& s, std::uint32_t k, int suppression)
{
  const RingLinks links{grid, s};
  for (const bool ahead : {true, false})  // each way up to a gap
  {
    std::uint32_t local = k;
    for (int i = 0; i < suppression; ++i)
    {
      const std::int64_t q = ahead ? links.next(local) : links.prev(local);
      if (q < 0) break;
      blocked_[static_cast<std::size_t>(q)] |= kSuppressed;
      local = static_cast<std::uint32_t>(q - s.b);
    }
  }
}

void LoamSelector::pick(const ScanGrid& grid, const RingSpan& s, std::vector<std::uint64_t>& cand, int quota, int suppression,
                        std::vector<std::uint32_t>& out, std::vector<std::uint32_t>* also, int also_quota)
{
  if (quota <= 0 || cand.empty()) return;
  // Each pick blocks at most 2 * suppression others, so the best quota * (2s + 1) suffice.
  // (Less sharp picks that block nothing only make that more than enough.)
  const std::size_t need = std::min(cand.size(), static_cast<std::size_t>(quota) * (2 * static_cast<std::size_t>(suppression) + 1));
  // The best `need` in linear time, then only those sorted.
  const auto mid = cand.begin() + static_cast<std::ptrdiff_t>(need);
  if (need < cand.size()) std::nth_element(cand.begin(), mid, cand.end());
  std::sort(cand.begin(), mid);
  int taken = 0;
  for (std::size_t i = 0; i < need && taken < quota; ++i)
  {
    const auto p = static_cast<std::uint32_t>(cand[i]);
    if (blocked_[p]) continue;
    out.push_back(p);
    // Only the points odometry matches (sharp, flat) keep their neighbours out; the less sharp
    // ones beyond them are map landmarks, and every Edge/Corner is one.
    const bool matched = !also || taken < also_quota;
    if (also && taken < also_quota) also->push_back(p);
    ++taken;
    blocked_[p] |= kSuppressed;
    if (matched) block(grid, s, p - s.b, suppression);
  }
}

void LoamSelector::lessFlat(const ScanGrid& grid, std::uint32_t b, std::uint32_t K, const std::vector<Label>& labels,
                            const Params& params, LoamFeatures& out)
{
  const float voxel = params.loam_less_flat_voxel;
  if (voxel <= 0.0f)
  {
    for (std::uint32_t p = b; p < b + K; ++p)
      if (labels[p] == Label::Plane && !(blocked_[p] & kExcluded)) out.less_flat.push_back(p);
    return;
  }
  // One point per voxel, the flat ones first so that the less flat set holds them (LOAM's
  // odometry matches the flat points of one frame to the less flat of the last).
  std::size_t cap = 16;
  int bits = 4;
  while (cap < 2 * static_cast<std::size_t>(K))
  {
    cap <<= 1;
    ++bits;
  }
  if (voxel_keys_.size() < cap) voxel_keys_.assign(cap, kNoKey);
  const std::size_t mask = cap - 1;
  const double inv = 1.0 / voxel;
  std::uint64_t last = kNoKey;  // (along a ring most points share their predecessor's voxel)
  const auto insert = [&](std::uint32_t p) {
    const std::uint64_t key = voxelKey(grid.x[p], grid.y[p], grid.z[p], inv);
    if (key == last) return false;
    last = key;
    // Fibonacci hashing: the product's top bits depend on every bit of the key (its low bits
    // would ignore x, and a ring's voxels would pile up in probe chains).
    std::size_t h = static_cast<std::size_t>((key * 0x9E3779B97F4A7C15ull) >> (64 - bits));
    while (voxel_keys_[h] != kNoKey)
    {
      if (voxel_keys_[h] == key) return false;
      h = (h + 1) & mask;
    }
    voxel_keys_[h] = key;
    voxel_used_.push_back(static_cast<std::uint32_t>(h));
    return true;
  };
  voxel_used_.clear();
  for (std::size_t i = out.flat.size(); i-- > 0 && out.flat[i] >= b;)
  {
    insert(out.flat[i]);
    out.less_flat.push_back(out.flat[i]);
  }
  for (std::uint32_t p = b; p < b + K; ++p)
    if (labels[p] == Label::Plane && !(blocked_[p] & kExcluded) && insert(p)) out.less_flat.push_back(p);
  for (const std::uint32_t h : voxel_used_) voxel_keys_[h] = kNoKey;
}

void LoamSelector::sweepTimes(const PointCloudView& view, const ScanGrid& grid, const Params& params, LoamFeatures& out)
{
  const std::size_t n = grid.size();
  out.sweep_time.resize(n);
  out.time_from_field = false;
  out.first_time = 0.0;
  const double period = params.scan_period;
  if (view.time.present() && n > 0)
  {
    time_scratch_.resize(n);
    double lo = std::numeric_limits<double>::infinity(), hi = -lo;
    if (view.time.type == ScalarType::Float32)
      readTimes(view, grid, [](const std::uint8_t* r) { return load<float>(r); }, time_scratch_, lo, hi);
    else if (view.time.type == ScalarType::Float64)
      readTimes(view, grid, [](const std::uint8_t* r) { return load<double>(r); }, time_scratch_, lo, hi);
    else if (view.time.type == ScalarType::UInt32)  // (ouster-ros `t`, nebula `time_stamp`: ns)
      readTimes(view, grid, [](const std::uint8_t* r) { return load<std::uint32_t>(r); }, time_scratch_, lo, hi);
    else
      readTimes(view, grid, [&view](const std::uint8_t* r) { return readScalar(r, view.time.type); }, time_scratch_, lo, hi);
    // A constant field (KITTI's bags carry time = 0) says nothing: fall back to the azimuth.
    if (std::isfinite(lo) && std::isfinite(hi) && (hi - lo) * view.time_scale > 1e-7)
    {
      for (std::size_t p = 0; p < n; ++p)
      {
        const double t = (time_scratch_[p] - lo) * view.time_scale;
        out.sweep_time[p] = static_cast<float>(std::min(std::max(t, 0.0), period));
      }
      out.time_from_field = true;
      out.first_time = lo * view.time_scale;
      return;
    }
  }
  if (n == 0) return;
  // The sweep starts where the first point in the input was fired.
  std::size_t first = 0;
  for (std::size_t p = 1; p < n; ++p)
    if (grid.index[p] < grid.index[first]) first = p;
  const double start = grid.azimuth[first], two_pi = 2.0 * kPiD;
  const double sign = params.sweep_clockwise ? -1.0 : 1.0;  // clockwise: azimuth falls with time
  for (std::size_t p = 0; p < n; ++p)
  {
    double turned = sign * (static_cast<double>(grid.azimuth[p]) - start);
    // (azimuths lie in one turn, so one wrap suffices: no std::floor call per point)
    if (turned < 0.0) turned += two_pi;
    if (turned >= two_pi) turned -= two_pi;
    turned += 0.0;  // (the first point's -0 of a clockwise sweep is +0, as the time of a sweep's start)
    out.sweep_time[p] = static_cast<float>(std::min(turned / two_pi * period, period));
  }
}

}  // namespace ring_curvature
