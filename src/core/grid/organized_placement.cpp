// The organized clouds' grid: a row is a ring and the columns are in azimuth order already, so
// placing a row's valid points is a compaction of the input pass's points.
#include "ring_curvature/scan_grid.hpp"
#include "grid/scan_grid_builder.hpp"

namespace ring_curvature
{

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

}  // namespace ring_curvature
