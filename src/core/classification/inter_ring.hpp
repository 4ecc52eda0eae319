// Inter-ring evidence on the ring-wise labels (the paper's section 6.2, "early, selective
// inter-ring fusion"): a ring alone cannot tell a hedge from a wall or a pole from a wall's edge,
// the rings above and below can. Five steps, each with its switch in Params:
// - roughness over a window of 3 or 5 rings x up to 9 samples: foliage is rough along and across
//   rings, a plane or a horizontal crease is not (its cross-ring residual is the same all along
//   the ring);
// - in a noisy frame, an Edge needs an Edge or Corner beside it on the ring above or below (a
//   crease crosses rings, noise does not line up);
// - no Edge or Corner in rough surroundings, but for outlines stacked over rings (a trunk's);
// - occlusion: only the near side of a depth jump is a Corner (the far side is its shadow);
// - thin objects: a narrow run in front of its neighbours (of one, where the other hides part of
//   it), stacked over rings, is Edge.
// Linear time: every position looks at O(1) neighbours, and the runs are one pass per ring.
#pragma once

#include "ring_curvature/features.hpp"
#include "ring_curvature/params.hpp"
#include "ring_curvature/scan_grid.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

namespace ring_curvature
{

class InterRingRefiner
{
public:
  /// Whether any of the steps is on (robust classifier only: Algorithm 1 stays the paper's).
  static bool enabled(const Params& params);
  /// Revises `labels` (per grid position) with the evidence of the neighbouring rings.
  void refine(const ScanGrid& grid, const Features& f, const Params& params, std::vector<Label>& labels);

private:
  /// Nearest samples on the rings above and below within 1.5 azimuth steps (up_, down_).
  void verticalNeighbours(const ScanGrid& grid);
  /// Per position: rough both along the ring (S) and across rings (the cross-ring residual).
  void roughness(const ScanGrid& grid, const Features& f, const Params& params);
  /// The lower quartile of the finite values (0 when none).
  float lowerQuartile(const std::vector<float>& values);
  /// Per position: samples and rough samples within rough_window_half along its ring (win_).
  void ringWindows(const ScanGrid& grid, const Params& params);
  /// win_ of p from its linked neighbours (ring ends and short rings, where the window may wrap).
  std::uint32_t walkedWindow(std::uint32_t p, int h, bool short_ring) const;
  /// Each position's share of rough samples in its window (its ring and `rings` above and below)
  /// into share_; with inter_ring_roughness, Plane and Rough labels decided by it on the way.
  void shares(int rings, const Params& params, std::vector<Label>& labels);
  /// The Edge and Corner labels' steps: Edge support, foliage, occlusion.
  void refineFeatures(const ScanGrid& grid, const Params& params, bool share_needed, std::vector<Label>& labels);
  /// Each sample's linked neighbours along its ring (prev_, next_).
  void ringLinks(const ScanGrid& grid);
  std::int32_t twoBack(std::uint32_t p) const
  {
    const std::int32_t q = prev_[p];
    return q >= 0 && prev_[static_cast<std::size_t>(q)] != static_cast<std::int32_t>(p) ? prev_[static_cast<std::size_t>(q)] : -1;
  }
  std::int32_t twoAhead(std::uint32_t p) const
  {
    const std::int32_t q = next_[p];
    return q >= 0 && next_[static_cast<std::size_t>(q)] != static_cast<std::int32_t>(p) ? next_[static_cast<std::size_t>(q)] : -1;
  }
  /// Per position: in a thin run (thin_).
  void thinRuns(const ScanGrid& grid, const Params& params);
  /// Whether q or a ring neighbour of it is flagged at about range r (a 1-sample pole is not
  /// always the nearest sample in azimuth on the next ring).
  template <class Flagged>
  bool near(std::int32_t q, double r, const double* rho, const Params& params, const Flagged& flagged) const
  {
    if (q < 0) return false;
    const double tol = std::max(static_cast<double>(params.thin_max_range_step), params.thin_range_step_ratio * r);
    for (const std::int32_t c : {q, prev_[static_cast<std::size_t>(q)], next_[static_cast<std::size_t>(q)]})
      if (c >= 0 && std::fabs(rho[c] - r) < tol && flagged(c)) return true;
    return false;
  }
  /// Whether p is stacked: flagged samples near its range in thin_min_stack of the 4 places 1 and
  /// 2 rings above and below.
  template <class Flagged>
  bool stacked(std::uint32_t p, const double* rho, const Params& params, const Flagged& flagged) const
  {
    const std::int32_t u = up_[p], d = down_[p];
    const std::int32_t places[4] = {u, d, u >= 0 ? up_[static_cast<std::size_t>(u)] : -1,
                                    d >= 0 ? down_[static_cast<std::size_t>(d)] : -1};
    int count = 0;
    for (int i = 0; i < 4; ++i)
    {
      if (count + 4 - i < params.thin_min_stack) return false;  // (the places left cannot make it)
      count += near(places[i], rho[p], rho, params, flagged) ? 1 : 0;
    }
    return count >= params.thin_min_stack;
  }
  /// Whether p is the near side of a depth jump or of a gap along its ring.
  bool silhouette(std::int32_t p, const double* rho, const Params& params) const;

  const std::int32_t* up_ = nullptr;     // the grid's own up where it needs no filter, else own_up_
  std::vector<std::int32_t> own_up_, down_;  // -1: none
  std::vector<std::int32_t> prev_, next_;  // linked neighbours along the ring, -1: none
  std::vector<std::uint32_t> win_;       // the window along the ring: samples | rough ones << 16
  std::vector<std::uint32_t> chain_[4];  // window sums up / down the rings (two buffers a side)
  std::vector<float> share_;             // share of rough samples in the window over rings
  std::vector<float> across_;            // rho - mean of the ranges above and below (NaN: none)
  std::vector<float> vert_, ring_s_;     // the cross-ring and ring-wise roughness, range-scaled
  std::vector<float> scratch_;
  float noise_sigma_ = 0.0f;             // the frame's range noise, estimated from vert_
  std::vector<std::uint8_t> rough_, thin_, run_break_, occluder_, ring_feature_;
};

}  // namespace ring_curvature
