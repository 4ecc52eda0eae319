// The inter-ring steps' neighbourhoods (see inter_ring.hpp): the linked neighbours along a ring,
// the nearest samples on the rings above and below, and the rough samples' share of each window
// over rings.
#include "classification/inter_ring.hpp"

#include "classification/rank_select.hpp"
#include "common/angles.hpp"
#include "common/ring_index.hpp"
#include "common/simd_clones.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace ring_curvature
{

namespace
{
constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();

// The range less the mean of the ranges above and below (NaN where either is missing): the same
// all along a ring on a plane, a horizontal crease or a beam's range bias, scattered on foliage.
// Branch-free: a missing neighbour reads the sample itself, then is masked.
RC_SIMD_CLONES void acrossRings(std::size_t m, const std::int32_t* __restrict up, const std::int32_t* __restrict down,
                                const double* __restrict rho, float* __restrict out)
{
  for (std::size_t p = 0; p < m; ++p)
  {
    const bool ok = (up[p] >= 0) & (down[p] >= 0);
    const auto self = static_cast<std::int32_t>(p);
    const double a = rho[p] - 0.5 * (rho[ok ? up[p] : self] + rho[ok ? down[p] : self]);
    out[p] = ok ? static_cast<float>(a) : kNaN;
  }
}

// The cross-ring scatter v = |a - (a_prev + a_next) / 2| and the ring-wise S, both relative to
// their growth with range beyond `scale` (the sample spacing grows with range).
RC_SIMD_CLONES void scaledRoughness(std::size_t m, const std::int32_t* __restrict prev,
                                    const std::int32_t* __restrict next, const float* __restrict across,
                                    const float* __restrict smoothness, const double* __restrict rho, float scale,
                                    float* __restrict vert, float* __restrict ring_s)
{
  for (std::size_t p = 0; p < m; ++p)
  {
    const bool ok = (prev[p] >= 0) & (next[p] >= 0);
    const auto self = static_cast<std::int32_t>(p);
    const float v = std::fabs(across[p] - 0.5f * (across[ok ? prev[p] : self] + across[ok ? next[p] : self]));
    const float inv = scale > 0 ? std::min(1.0f, scale / static_cast<float>(rho[p])) : 1.0f;
    vert[p] = ok ? v * inv : kNaN;
    ring_s[p] = smoothness[p] * (inv * inv);
  }
}

// Inside a ring every sample's neighbours are the positions beside it (if linked); the ring's
// ends are set after.
RC_SIMD_CLONES void innerLinks(std::size_t m, const std::uint8_t* __restrict linked, std::int32_t* __restrict prev,
                               std::int32_t* __restrict next)
{
  for (std::size_t p = 1; p + 1 < m; ++p)
  {
    const auto self = static_cast<std::int32_t>(p);
    next[p] = linked[p + 1] != 0 ? self + 1 : -1;
    prev[p] = linked[p] != 0 ? self - 1 : -1;
  }
}

// The grid's nearest sample above, kept within tol in azimuth.
RC_SIMD_CLONES void upWithin(std::size_t m, float tol, const std::int32_t* __restrict grid_up,
                             const float* __restrict az, std::int32_t* __restrict up)
{
  for (std::size_t p = 0; p < m; ++p)
  {
    const std::int32_t u = grid_up[p];
    const float d = circularDistance(az[p] - az[u >= 0 ? u : static_cast<std::int32_t>(p)]);
    up[p] = u >= 0 && d <= tol ? u : -1;
  }
}

// Organized: the same column one row down (none on the first row).
RC_SIMD_CLONES void downOrganized(std::size_t m, std::size_t width, const std::uint32_t* __restrict index,
                                  const std::int32_t* __restrict grid_pos, std::int32_t* __restrict down)
{
  for (std::size_t p = 0; p < m; ++p)
  {
    const std::uint32_t i = index[p];
    const std::int32_t d = grid_pos[i >= width ? i - width : i];
    down[p] = i >= width ? d : -1;
  }
}

// The grid's `below` q or the one after it (around the seam: the ring's last or first), whichever
// is nearer, if within tol. A loop of its own so that the coin tosses are selections, not branches.
RC_SIMD_CLONES void nearestBelow(std::uint32_t b, std::uint32_t e, std::uint32_t bb, std::uint32_t be, float tol,
                                 const float* __restrict az, const std::int32_t* __restrict below,
                                 std::int32_t* __restrict down)
{
  for (std::uint32_t p = b; p < e; ++p)
  {
    const float a = az[p];
    const auto q = static_cast<std::uint32_t>(below[p]);
    const bool before = az[q] <= a;
    const std::uint32_t lo = before ? q : be - 1, hi = q + 1 < be && before ? q + 1 : bb;
    const float d_lo = circularDistance(a - az[lo]), d_hi = circularDistance(az[hi] - a);
    const std::uint32_t best = d_hi < d_lo ? hi : lo;
    down[p] = std::min(d_lo, d_hi) <= tol ? static_cast<std::int32_t>(best) : -1;
  }
}

// The window of each p in [lo, hi) where it cannot leave p's ring (h samples each way; a sample
// counts while no gap lies between it and p): samples | rough samples << 16. Blocks of positions
// so that the byte counters stay in L1 across the 2h shifted passes.
RC_SIMD_CLONES void innerWindows(std::size_t lo, std::size_t hi, int h, const std::uint8_t* __restrict linked,
                                 const std::uint8_t* __restrict rough, std::uint32_t* __restrict win)
{
  constexpr std::size_t kBlock = 512;
  std::uint8_t ahead[kBlock], back[kBlock], total[kBlock], hits[kBlock];
  for (std::size_t b0 = lo; b0 < hi; b0 += kBlock)
  {
    const std::size_t n = std::min(kBlock, hi - b0);
    const std::uint8_t* const L = linked + b0;
    const std::uint8_t* const R = rough + b0;
    for (std::size_t i = 0; i < n; ++i)
    {
      ahead[i] = back[i] = total[i] = 1;
      hits[i] = R[i];
    }
    for (std::ptrdiff_t k = 1; k <= h; ++k)
      for (std::size_t i = 0; i < n; ++i)
      {
        const auto j = static_cast<std::ptrdiff_t>(i);
        ahead[i] &= L[j + k];
        back[i] &= L[j - k + 1];
        total[i] = static_cast<std::uint8_t>(total[i] + ahead[i] + back[i]);
        hits[i] = static_cast<std::uint8_t>(hits[i] + (ahead[i] & R[j + k]) + (back[i] & R[j - k]));
      }
    for (std::size_t i = 0; i < n; ++i) win[b0 + i] = total[i] | static_cast<std::uint32_t>(hits[i]) << 16;
  }
}

// One more ring along `side`: out[q] = win[q] + cur[side[q]] (nothing past the last ring).
RC_SIMD_CLONES void chainStep(std::size_t m, const std::uint32_t* __restrict win, const std::int32_t* __restrict side,
                              const std::uint32_t* __restrict cur, std::uint32_t* __restrict out)
{
  for (std::size_t q = 0; q < m; ++q)
  {
    const std::int32_t s = side[q];
    const std::uint32_t c = cur[s >= 0 ? s : static_cast<std::int32_t>(q)];
    out[q] = win[q] + (s >= 0 ? c : 0u);
  }
}

// The share of rough samples in the window over rings of each p (its own window, and the chains
// up and down from its neighbours above and below).
RC_SIMD_CLONES void windowShares(std::size_t m, const std::uint32_t* __restrict win, const std::int32_t* __restrict up,
                                 const std::int32_t* __restrict down, const std::uint32_t* __restrict chain_up,
                                 const std::uint32_t* __restrict chain_down, float* __restrict share)
{
  for (std::size_t p = 0; p < m; ++p)
  {
    const auto self = static_cast<std::int32_t>(p);
    const std::int32_t u = up[p], d = down[p];
    const std::uint32_t cu = chain_up[u >= 0 ? u : self], cd = chain_down[d >= 0 ? d : self];
    const std::uint32_t s = win[p] + (u >= 0 ? cu : 0u) + (d >= 0 ? cd : 0u);
    const std::uint32_t total = s & 0xffffu, rough = s >> 16;
    share[p] = total > 0 ? static_cast<float>(rough) / static_cast<float>(total) : 0.0f;
  }
}

// Plane and Rough (the ring-wise roughness) decided by the window's share instead.
RC_SIMD_CLONES void windowLabels(std::size_t m, const float* __restrict share, float fraction, Label* __restrict labels)
{
  for (std::size_t p = 0; p < m; ++p)
  {
    const Label l0 = labels[p];
    const Label l = share[p] >= fraction ? Label::Rough : Label::Plane;
    labels[p] = l0 == Label::Plane || l0 == Label::Rough ? l : l0;
  }
}

}  // namespace

void InterRingRefiner::ringLinks(const ScanGrid& g)
{
  const std::size_t m = g.size();
  prev_.resize(m);
  next_.resize(m);
  innerLinks(m, g.linked.data(), prev_.data(), next_.data());
  for (std::int32_t n = 0; n < g.num_rings; ++n)
  {
    const RingSpan R(g, n);
    if (R.end() == R.b) continue;
    for (const std::uint32_t p : {R.b, R.end() - 1})
    {
      // linked[q]: q joins its predecessor (a closed ring's first sample its last, across the seam)
      const std::uint32_t after = p + 1 < R.end() ? p + 1 : R.b, before = p > R.b ? p - 1 : R.end() - 1;
      const bool ahead = (p + 1 < R.end() || R.closed) && g.linked[after] != 0 && after != p;
      const bool back = g.linked[p] != 0 && before != p;
      next_[p] = ahead ? static_cast<std::int32_t>(after) : -1;
      prev_[p] = back ? static_cast<std::int32_t>(before) : -1;
    }
  }
}

void InterRingRefiner::verticalNeighbours(const ScanGrid& g)
{
  const std::size_t m = g.size();
  down_.resize(m);
  if (g.up.size() != m || (!g.organized && g.below.size() != m))
  {
    own_up_.assign(m, -1);
    up_ = own_up_.data();
    std::fill(down_.begin(), down_.end(), -1);
    return;
  }
  if (g.organized)
  {
    // a column is one firing: the same column one row up (the grid's up) and down (beams may
    // have azimuth offsets)
    up_ = g.up.data();
    const std::size_t width = g.num_input / static_cast<std::size_t>(std::max(g.num_rings, 1));
    downOrganized(m, width, g.index.data(), g.grid_pos.data(), down_.data());
    return;
  }
  const float tol = 1.5f * g.azimuth_resolution;
  const float* const az = g.azimuth.data();
  own_up_.resize(m);
  upWithin(m, tol, g.up.data(), az, own_up_.data());
  up_ = own_up_.data();
  // the nearest sample on the ring below: the grid's last one at or before p's azimuth (found in
  // the same walk as up) or the one after it
  for (int n = 0; n < g.num_rings; ++n)
  {
    const RingSpan R(g, n);
    if (n == 0 || g.ring_begin[static_cast<std::size_t>(n)] == g.ring_begin[static_cast<std::size_t>(n) - 1])
    {
      std::fill(down_.begin() + R.b, down_.begin() + R.end(), -1);
      continue;
    }
    const RingSpan B(g, n - 1);
    nearestBelow(R.b, R.end(), B.b, B.end(), tol, az, g.below.data(), down_.data());
  }
}

void InterRingRefiner::roughness(const ScanGrid& g, const Features& f, const Params& P)
{
  const std::size_t m = g.size();
  across_.resize(m);
  vert_.resize(m);
  ring_s_.resize(m);
  rough_.resize(m);
  acrossRings(m, up_, down_.data(), g.range.data(), across_.data());
  scaledRoughness(m, prev_.data(), next_.data(), across_.data(), f.smoothness.data(), g.range.data(),
                  P.rough_range_scale, vert_.data(), ring_s_.data());
  // The bounds follow the frame's own noise: a multiple of the lower quartile of each measure
  // (most samples are planes, and foliage rarely reaches the lower quartile), never below the
  // fixed minimum that a quiet sensor needs.
  const float v_lq = lowerQuartile(vert_);
  // v of Gaussian range noise sigma: |N(0, 1.5 sigma)|, whose lower quartile is 0.48 sigma
  noise_sigma_ = v_lq / 0.48f;
  const float v_thr = std::max(P.rough_vertical_min, P.rough_noise_k * v_lq);
  const float s_thr = std::max(P.rough_smoothness_min, P.rough_noise_k * P.rough_noise_k * lowerQuartile(ring_s_));
  for (std::size_t p = 0; p < m; ++p) rough_[p] = (ring_s_[p] > s_thr) & (vert_[p] > v_thr);
  ringWindows(g, P);
}

void InterRingRefiner::ringWindows(const ScanGrid& g, const Params& P)
{
  const std::size_t m = rough_.size();
  const int h = P.rough_window_half;
  const auto uh = static_cast<std::uint32_t>(h);
  win_.resize(m);
  // inside a ring, a window is the stretch of p's linked segment within h of it; within h of the
  // ring's ends (where a closed ring's window crosses the seam) and on a ring of at most 2h + 1
  // samples (where the walks back and ahead meet), the links are walked
  if (m > 2 * static_cast<std::size_t>(h)) innerWindows(uh, m - uh, h, g.linked.data(), rough_.data(), win_.data());
  for (std::int32_t n = 0; n < g.num_rings; ++n)
  {
    const RingSpan R(g, n);
    if (R.end() == R.b) continue;
    const bool short_ring = R.end() - R.b <= 2 * uh + 1;
    const std::uint32_t head_end = short_ring ? R.end() : R.b + uh;
    for (std::uint32_t p = R.b; p < head_end; ++p) win_[p] = walkedWindow(p, h, short_ring);
    if (!short_ring)
      for (std::uint32_t p = R.end() - uh; p < R.end(); ++p) win_[p] = walkedWindow(p, h, false);
  }
}

std::uint32_t InterRingRefiner::walkedWindow(std::uint32_t p, int h, bool short_ring) const
{
  std::int32_t back[4];
  int nb = 0, total = 1, rough = rough_[p];
  for (std::int32_t q = prev_[p]; q >= 0 && q != static_cast<std::int32_t>(p) && nb < h; q = prev_[static_cast<std::size_t>(q)])
  {
    back[nb++] = q;
    rough += rough_[static_cast<std::size_t>(q)];
  }
  total += nb;
  int na = 0;
  for (std::int32_t q = next_[p]; q >= 0 && q != static_cast<std::int32_t>(p) && na < h;
       q = next_[static_cast<std::size_t>(q)], ++na)
  {
    if (short_ring && std::find(back, back + nb, q) != back + nb) break;
    ++total;
    rough += rough_[static_cast<std::size_t>(q)];
  }
  return static_cast<std::uint8_t>(total) | static_cast<std::uint32_t>(static_cast<std::uint8_t>(rough)) << 16;
}

void InterRingRefiner::shares(int rings, const Params& P, std::vector<Label>& labels)
{
  // (rings >= 1: the window always spans the rings beside p)
  const std::size_t m = win_.size();
  share_.resize(m);
  // chain[q]: the windows of q and of up to rings - 1 more along the side, each ring's counts
  // below 256 and at most 256 rings, so the samples never carry into the rough ones
  const std::uint32_t* chains[2] = {win_.data(), win_.data()};
  const std::int32_t* const sides[2] = {up_, down_.data()};
  for (int s = 0; s < 2; ++s)
    for (int k = 1; k < rings; ++k)
    {
      std::vector<std::uint32_t>& out = chain_[2 * s + (k & 1)];
      out.resize(m);
      chainStep(m, win_.data(), sides[s], chains[s], out.data());
      chains[s] = out.data();
    }
  windowShares(m, win_.data(), up_, down_.data(), chains[0], chains[1], share_.data());
  if (P.inter_ring_roughness) windowLabels(m, share_.data(), P.rough_window_fraction, labels.data());
}

float InterRingRefiner::lowerQuartile(const std::vector<float>& values)
{
  // every 4th value: the quartile of a frame's 10^4-10^5 samples needs no more
  scratch_.clear();
  for (std::size_t i = 0; i < values.size(); i += 4)
    if (std::isfinite(values[i])) scratch_.push_back(values[i]);
  return scratch_.empty() ? 0.0f : selectNth(scratch_.data(), scratch_.size(), scratch_.size() / 4);
}

}  // namespace ring_curvature
