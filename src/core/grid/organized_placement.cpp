// The organized clouds' grid: a row is a ring and the columns are in azimuth order already, so
// placing a row's valid points is a compaction of the input pass's points. On AVX2 CPUs the
// float32 x, y, z layout takes the input pass and the placement in one (readOrganized).
#include "ring_curvature/scan_grid.hpp"
#include "grid/scan_grid_builder.hpp"

#include "common/float_bits.hpp"
#include "grid/organized_avx2.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>

namespace ring_curvature
{

namespace
{
#if defined(RC_SIMD_CLONES_ON)
// One column of the fused pass: a lane of readPlaceRowAvx2, operation for operation (the input
// pass's range and validity, fastAtan2, the placement at w, z / range added to s).
std::size_t placeColumn(const std::uint8_t* rec, const detail::RecordLayout& L, const detail::OrganizedGrid& out,
                        std::size_t i, std::size_t w, double& s, std::uint32_t& largest)
{
  const float x = readFloat32(rec + L.ox), y = readFloat32(rec + L.oy), z = readFloat32(rec + L.oz);
  const double dx = x, dy = y, dz = z;
  const double r = std::sqrt(dx * dx + dy * dy + dz * dz);
  const bool ok = (r >= L.rmin) & (r <= L.rmax);
  if (L.oring >= 0)
  {
    std::uint16_t r16;
    std::memcpy(&r16, rec + L.oring, sizeof r16);
    largest = std::max<std::uint32_t>(largest, r16);
  }
  out.state[i] = ok ? PointState::OnGrid : PointState::Invalid;
  out.index[w] = static_cast<std::uint32_t>(i);
  out.az[w] = fastAtan2(y, x);
  out.x[w] = dx;
  out.y[w] = dy;
  out.z[w] = dz;
  out.range[w] = r;
  out.grid_pos[i] = ok ? static_cast<std::int32_t>(w) : -1;
  if (ok) s += dz / r;
  return w + (ok ? 1 : 0);
}
#endif
}  // namespace

void ScanGridBuilder::placeOrganized(const PointCloudView& view, ScanGrid& grid)
{
  const std::size_t R = view.height, W = view.width;
  grid.ring_begin.assign(R + 1, 0);
  // Branch-free compaction into presized arrays (NaN-padded sensors make validity a coin toss
  // per point): every point is written at w, only valid ones advance it.
  tmp_index_.resize(R * W + 1);
  sorted_az_.resize(R * W + 1);
  std::uint32_t* const index = tmp_index_.data();
  float* const az = sorted_az_.data();
  const std::int32_t* const ring = ring_of_.data();
  std::size_t w = 0;
  for (std::size_t r = 0; r < R; ++r)
  {
    for (std::size_t c = 0; c < W; ++c)
    {
      const std::size_t i = r * W + c;
      index[w] = static_cast<std::uint32_t>(i);
      az[w] = paz_[i];
      w += ring[i] >= 0 ? 1 : 0;
    }
    grid.ring_begin[r + 1] = static_cast<std::uint32_t>(w);
  }
  tmp_index_.resize(w);
  sorted_az_.resize(w);
}

bool ScanGridBuilder::readOrganized(const PointCloudView& view, const Params& params, ScanGrid& grid,
                                    std::uint32_t& largest)
{
#if defined(RC_SIMD_CLONES_ON)
  const auto f32 = [](const FieldView& f) { return f.type == ScalarType::Float32; };
  const bool ring16 = !view.ring.present() || view.ring.type == ScalarType::UInt16;
  if (!f32(view.x) || !f32(view.y) || !f32(view.z) || !ring16 || view.y.offset != view.x.offset + 4 ||
      view.z.offset != view.x.offset + 8 || !__builtin_cpu_supports("avx2") || !__builtin_cpu_supports("popcnt"))
    return false;
  const std::size_t R = view.height, W = view.width, n = R * W;
  const std::size_t room = n + 8;  // the vector stores write up to 8 past the last point
  tmp_index_.resize(room);
  sorted_az_.resize(room);
  for (auto* v : {&grid.x, &grid.y, &grid.z, &grid.range}) v->resize(room);
  ring_sum_.assign(R, 0.0);
  grid.ring_begin.assign(R + 1, 0);
  const detail::RecordLayout L{view.point_step,
                               static_cast<std::size_t>(view.x.offset),
                               static_cast<std::size_t>(view.y.offset),
                               static_cast<std::size_t>(view.z.offset),
                               view.ring.present() ? static_cast<std::ptrdiff_t>(view.ring.offset) : -1,
                               params.min_range,
                               params.max_range};
  const detail::OrganizedGrid out{tmp_index_.data(), sorted_az_.data(), grid.x.data(),        grid.y.data(),
                                  grid.z.data(),     grid.range.data(), grid.grid_pos.data(), grid.state.data()};
  std::size_t w = 0;
  largest = 0;
  for (std::size_t r = 0; r < R; ++r)
  {
    // (the last record's 16 bytes from x or 4 at its ring could pass the end of the data: the
    // last row's last group goes one column at a time)
    const std::size_t vector_cols = (r + 1 < R ? W : W - 1) / 8 * 8;
    const std::uint8_t* const row = view.data + r * view.row_step;
    w = detail::readPlaceRowAvx2(row, L, out, r * W, vector_cols, w, ring_sum_[r], largest);
    for (std::size_t c = vector_cols; c < W; ++c)
      w = placeColumn(row + c * L.step, L, out, r * W + c, w, ring_sum_[r], largest);
    grid.ring_begin[r + 1] = static_cast<std::uint32_t>(w);
  }
  tmp_index_.resize(w);
  sorted_az_.resize(w);
  return true;
#else
  (void)view;
  (void)params;
  (void)grid;
  (void)largest;
  return false;
#endif
}

}  // namespace ring_curvature
