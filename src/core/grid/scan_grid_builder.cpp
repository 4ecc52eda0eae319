// The grid stage's driver (build), dual returns, the gather in grid order and the links along
// rings; the other steps have files of their own (see scan_grid_builder.hpp).
#include "ring_curvature/scan_grid.hpp"
#include "grid/scan_grid_builder.hpp"

#include "common/angles.hpp"
#include "grid/cloud_view_checks.hpp"
#include "grid/record_read.hpp"
#include "common/simd_clones.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>

namespace ring_curvature
{

namespace
{

// Grid coordinates from the input pass's float32 copies (float32 widens to double exactly).
RC_SIMD_CLONES void gatherXyz(std::size_t m, const std::uint32_t* __restrict index, const float* __restrict px,
                              const float* __restrict py, const float* __restrict pz, const double* __restrict prange,
                              double* __restrict gx, double* __restrict gy, double* __restrict gz,
                              double* __restrict gr)
{
  for (std::size_t p = 0; p < m; ++p)
  {
    const std::uint32_t i = index[p];
    gx[p] = px[i];
    gy[p] = py[i];
    gz[p] = pz[i];
    gr[p] = prange[i];
  }
}

// How many samples from p on (whole groups of eight, before e) are each at least `same_firing`
// after their predecessor: the stretch removeDuplicates keeps as is (NaN counts as kept, as there).
std::uint32_t keptStretch(const float* az, std::uint32_t p, std::uint32_t e, float same_firing)
{
  std::uint32_t q = p;
  for (; q + 8 <= e; q += 8)
  {
    bool close = false;
    for (std::uint32_t t = q; t < q + 8; ++t) close |= az[t] - az[t - 1] < same_firing;
    if (close) break;
  }
  return q - p;
}

// Links along a ring (b, e) against each predecessor, in loops of their own so that they vectorize.
RC_SIMD_CLONES void linkAzimuths(std::size_t b, std::size_t e, const float* __restrict az, float max_step,
                                 std::uint8_t* __restrict linked)
{
  for (std::size_t p = b + 1; p < e; ++p) linked[p] = az[p] - az[p - 1] <= max_step ? 1 : 0;
}
// (`index`: the input indices, whose differences in a row of an organized cloud are its columns')
RC_SIMD_CLONES void linkColumns(std::size_t b, std::size_t e, const std::uint32_t* __restrict index,
                                std::uint32_t max_cols, std::uint8_t* __restrict linked)
{
  for (std::size_t p = b + 1; p < e; ++p) linked[p] = index[p] - index[p - 1] <= max_cols ? 1 : 0;
}

// The input indices i in [0, n) with state[i] == Duplicate, ascending, to out (one slot past
// them is written); returns how many. Branch-free: in dual-return frames the test is a coin toss.
std::size_t listDuplicates(const PointState* state, std::size_t n, std::uint32_t* out)
{
  std::size_t count = 0;
  for (std::size_t i = 0; i < n; ++i)
  {
    out[count] = static_cast<std::uint32_t>(i);
    count += state[i] == PointState::Duplicate ? 1 : 0;
  }
  return count;
}

}  // namespace

int ScanGrid::ringOf(std::uint32_t pos) const
{
  const auto it = std::upper_bound(ring_begin.begin(), ring_begin.end(), pos);
  return static_cast<int>(it - ring_begin.begin()) - 1;
}

Status ScanGridBuilder::build(const PointCloudView& view, const Params& params, ScanGrid& grid)
{
  // An empty grid, also what a rejected frame leaves (the input pass sizes the per-point arrays,
  // and readOrganized the grid's, before it meets a bad ring).
  const auto clear = [&grid] {
    grid.num_rings = 0;
    grid.ring_begin.assign(1, 0);
    grid.num_input = grid.num_valid = grid.num_duplicates = grid.num_second_returns = grid.num_folded = 0;
    for (auto* v : {&grid.x, &grid.y, &grid.z, &grid.range}) v->clear();
    grid.index.clear();
    grid.state.clear();
    grid.grid_pos.clear();
    grid.azimuth.clear();
    grid.duplicates.clear();
    grid.linked.clear();
    grid.up.clear();
    grid.below.clear();
  };
  clear();
  grid.organized = view.organized();

  Status st = checkLayout(view, params);
  if (!st) return st;
  if (view.size() == 0) return Status::success();

  st = readPoints(view, params, grid);
  if (!st)
  {
    clear();
    return st;
  }
  if (params.ring_from_elevation && !view.ring.present() && !view.organized()) assignRingsFromElevation(view, params, grid);
  if (view.organized())
  {
    if (!placed_) placeOrganized(view, grid);
  }
  else
    sortRings(grid, params.duplicate_azimuth_fraction > 0.0f);
  measureResolution(params, grid);
  if (!view.organized()) removeDuplicates(params, grid);

  gatherGrid(view, grid);
  if (!view.organized()) resolveFollowers(grid);  // needs the grid positions just set
  // The Duplicate points in ascending input order (their grid_pos was set by removeDuplicates).
  grid.duplicates.clear();
  if (grid.num_duplicates > 0)
  {
    grid.duplicates.resize(grid.num_input + 1);  // (listDuplicates writes one slot past them)
    grid.duplicates.resize(listDuplicates(grid.state.data(), grid.num_input, grid.duplicates.data()));
  }
  linkRings(params, grid);
  findVerticalNeighbours(grid);
  return Status::success();
}

// The structure-of-arrays grid in final order: coordinates, ranges, grid positions and each
// ring's mean elevation.
void ScanGridBuilder::gatherGrid(const PointCloudView& view, ScanGrid& grid)
{
  // float32 clouds take x, y, z from the input pass's compact copies (float32 widens exactly);
  // others read their records (float64 keeps its precision). Order and azimuths move by swap.
  const std::size_t m = tmp_index_.size();
  grid.index.swap(tmp_index_);
  grid.azimuth.swap(sorted_az_);
  // Both buffers of each pair take the larger capacity: otherwise they would alternate roles
  // with unequal capacities, and a large frame could meet the smaller one long after warm-up.
  tmp_index_.reserve(grid.index.capacity());
  sorted_az_.reserve(grid.azimuth.capacity());
  grid.x.resize(m);
  grid.y.resize(m);
  grid.z.resize(m);
  grid.range.resize(m);
  grid.num_valid = m;
  grid.ring_elevation.assign(static_cast<std::size_t>(grid.num_rings), 0.0f);
  grid.ring_cos.assign(static_cast<std::size_t>(grid.num_rings), 1.0f);
  double* const gx = grid.x.data();
  double* const gy = grid.y.data();
  double* const gz = grid.z.data();
  double* const gr = grid.range.data();
  const std::uint32_t* const index = grid.index.data();
  const bool fast = view.x.type == ScalarType::Float32 && view.y.type == ScalarType::Float32 &&
                    view.z.type == ScalarType::Float32;
  if (placed_)
  {
    // readOrganized wrote x, y, z, range, the grid positions and each ring's sum already
  }
  else if (fast)
  {
    gatherXyz(m, index, px_.data(), py_.data(), pz_.data(), prange_.data(), gx, gy, gz, gr);
  }
  else
  {
    for (std::size_t p = 0; p < m; ++p)
    {
      const std::uint32_t i = index[p];
      const std::uint8_t* const rec = view.record(i);
      gx[p] = readCoord(rec, view.x);
      gy[p] = readCoord(rec, view.y);
      gz[p] = readCoord(rec, view.z);
      gr[p] = prange_[i];
    }
  }
  // Grid positions, and the mean elevation of each ring (for the cone's development factor
  // cos(phi)), summed in grid order.
  for (int n = 0; n < grid.num_rings; ++n)
  {
    const std::uint32_t b = grid.ring_begin[static_cast<std::size_t>(n)], e = grid.ring_begin[static_cast<std::size_t>(n) + 1];
    double s = 0;
    if (placed_)
      s = ring_sum_[static_cast<std::size_t>(n)];  // (and the grid positions set)
    else
      for (std::uint32_t p = b; p < e; ++p)
      {
        grid.grid_pos[index[p]] = static_cast<std::int32_t>(p);
        s += gz[p] / gr[p];
      }
    const double sine = e > b ? std::clamp(s / (e - b), -1.0, 1.0) : 0.0;
    grid.ring_elevation[static_cast<std::size_t>(n)] = static_cast<float>(std::asin(sine));
    grid.ring_cos[static_cast<std::size_t>(n)] = static_cast<float>(std::sqrt(1.0 - sine * sine));
  }
}

void ScanGridBuilder::removeDuplicates(const Params& params, ScanGrid& grid)
{
  // Returns of the same firing (dual-return mode) sit at (almost) the same azimuth. An identical
  // one is a Duplicate that shares its representative's label; a different range is a second
  // return kept off the grid, so the ring stays a curve (one sample per firing).
  const float same_firing = params.duplicate_azimuth_fraction * grid.azimuth_resolution;
  const float same_range = std::max(params.range_noise, 0.005f);
  std::uint32_t w = 0;
  std::uint32_t new_begin = 0;
  std::size_t duplicates = 0, removed = 0;
  for (int n = 0; n < grid.num_rings; ++n)
  {
    const std::uint32_t b = grid.ring_begin[static_cast<std::size_t>(n)], e = grid.ring_begin[static_cast<std::size_t>(n) + 1];
    grid.ring_begin[static_cast<std::size_t>(n)] = new_begin;
    std::int64_t rep = -1;  // input index of the current representative
    float rep_az = 0.0f;
    for (std::uint32_t p = b; p < e; ++p)
    {
      // A stretch each at least a firing after its predecessor is kept whole: each is that far
      // from the representative too, so the loop below would keep every one.
      if (rep >= 0)
      {
        const std::uint32_t k = keptStretch(sorted_az_.data(), p, e, same_firing);
        if (k > 0)
        {
          if (w != p)
          {
            std::memmove(tmp_index_.data() + w, tmp_index_.data() + p, k * sizeof(std::uint32_t));
            std::memmove(sorted_az_.data() + w, sorted_az_.data() + p, k * sizeof(float));
          }
          w += k;
          p += k;
          rep = tmp_index_[w - 1];
          rep_az = sorted_az_[w - 1];
          if (p >= e) break;
        }
      }
      const std::uint32_t i = tmp_index_[p];
      const float az = sorted_az_[p];
      if (rep >= 0 && az - rep_az < same_firing)
      {
        // The first return of a firing stays on the grid (deterministic; both returns of a
        // dual-return firing lie on the same ray, so either continues the ring's curve).
        const std::size_t ri = static_cast<std::size_t>(rep);
        const bool same = std::fabs(prange_[i] - prange_[ri]) <= static_cast<double>(same_range);
        grid.state[i] = same ? PointState::Duplicate : PointState::SecondReturn;
        duplicates += same ? 1 : 0;  // in a register (see resolveFollowers)
        ++removed;
        grid.grid_pos[i] = static_cast<std::int32_t>(w - 1);  // the representative's grid position
        continue;
      }
      tmp_index_[w] = i;
      sorted_az_[w++] = az;
      rep = i;
      rep_az = az;
    }
    new_begin = w;
  }
  grid.num_duplicates += duplicates;
  grid.num_second_returns += removed - duplicates;
  grid.ring_begin[static_cast<std::size_t>(grid.num_rings)] = w;
  tmp_index_.resize(w);
  sorted_az_.resize(w);
}

void ScanGridBuilder::linkRings(const Params& params, ScanGrid& grid)
{
  const std::size_t m = grid.size();
  grid.linked.resize(m);  // every entry is written below: each ring's first by its seam test
  grid.ring_closed.assign(static_cast<std::size_t>(grid.num_rings), 0);
  const float max_step = (static_cast<float>(params.max_gap_samples) + 1.5f) * grid.azimuth_resolution;
  const std::uint32_t max_cols = static_cast<std::uint32_t>(params.max_gap_samples) + 1;
  std::uint8_t* const linked = grid.linked.data();
  for (int n = 0; n < grid.num_rings; ++n)
  {
    const std::uint32_t b = grid.ring_begin[static_cast<std::size_t>(n)], e = grid.ring_begin[static_cast<std::size_t>(n) + 1];
    if (e - b < 2)
    {
      if (e > b) linked[b] = 0;
      continue;
    }
    if (grid.organized)
      linkColumns(b, e, grid.index.data(), max_cols, linked);
    else
      linkAzimuths(b, e, grid.azimuth.data(), max_step, linked);
    // The seam: the last sample connects to the first when the ring covers the full circle.
    bool closed;
    if (grid.organized)
    {
      const float sweep = static_cast<float>(grid.num_input / static_cast<std::size_t>(grid.num_rings)) * grid.azimuth_resolution;
      const std::uint32_t width = static_cast<std::uint32_t>(grid.num_input / static_cast<std::size_t>(grid.num_rings));
      // (the input indices' difference is the columns': the same row)
      const std::uint32_t across = grid.index[b] + width - grid.index[e - 1];
      closed = std::fabs(sweep - kTwoPi) < 0.05f * kTwoPi && across <= max_cols;
    }
    else
    {
      closed = grid.azimuth[b] + kTwoPi - grid.azimuth[e - 1] <= max_step;
    }
    closed = closed && e - b >= 3;
    grid.ring_closed[static_cast<std::size_t>(n)] = closed ? 1 : 0;
    linked[b] = closed ? 1 : 0;
  }
}

}  // namespace ring_curvature
