// Inter-ring evidence on the ring-wise labels (see inter_ring.hpp).
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
constexpr double kFar = std::numeric_limits<double>::infinity();

// A depth jump between ranges r1 and r2.
inline bool isJump(double r1, double r2, const Params& P)
{
  return std::fabs(r1 - r2) > std::max(static_cast<double>(P.occlusion_min_jump),
                                       static_cast<double>(P.jump_min_ratio) * std::min(r1, r2));
}

// The range less the mean of the ranges above and below (NaN where either is missing): the same
// all along a ring on a plane, a horizontal crease or a beam's range bias, scattered on foliage.
// Branch-free (a missing neighbour reads the sample itself, then is masked) so that it vectorizes.
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

}  // namespace

bool InterRingRefiner::enabled(const Params& P)
{
  // Algorithm 1 (quartile mode) stays as the paper wrote it
  return P.classifier_mode == ClassifierMode::Robust &&
         (P.inter_ring_roughness || P.edge_vertical_support || P.suppress_foliage_features || P.occlusion_aware_jumps ||
          P.thin_objects);
}

void InterRingRefiner::refine(const ScanGrid& g, const Features& f, const Params& P, std::vector<Label>& labels)
{
  const std::size_t m = g.size();
  if (m == 0 || !enabled(P)) return;
  ringLinks(g);
  verticalNeighbours(g);
  const bool share_needed = P.inter_ring_roughness || P.suppress_foliage_features;
  // auto: 5 rings where they are dense (>= 32), else 3 (a 16-ring sensor's 5 rings span a hedge)
  const int window_rings = P.rough_window_rings > 0 ? P.rough_window_rings : (g.num_rings >= 32 ? 2 : 1);
  if (share_needed) roughness(g, f, P);
  const bool keep_silhouettes = P.suppress_foliage_features && P.foliage_keep_silhouettes;
  // in place: each sample reads and writes only its own label (no step makes a label None); a
  // Corner moved to the near side of its jump is marked in occluder_ and set after the pass
  const double* const rho = g.range.data();
  if (P.occlusion_aware_jumps) occluder_.assign(m, 0);
  const bool edge_support = P.edge_vertical_support && (!share_needed || noise_sigma_ > P.edge_support_noise);
  if (edge_support)
  {
    ring_feature_.resize(m);
    for (std::uint32_t p = 0; p < m; ++p)
      ring_feature_[p] = labels[p] == Label::Edge || labels[p] == Label::Corner ? 1 : 0;
  }
  for (std::uint32_t p = 0; p < m; ++p)
  {
    const Label l0 = labels[p];
    if (l0 == Label::None) continue;
    Label l = l0;
    const float share = share_needed ? roughShare(p, window_rings) : 0.0f;
    // a crease crosses rings, range noise does not line up from one ring to the next; asked only
    // of a noisy frame (a fold along the ring, e.g. a wall's foot, has no Edge on the rings beside
    // it, and a quiet sensor's ring-wise Edges are reliable)
    const auto ring_feature = [this](std::int32_t c) { return ring_feature_[static_cast<std::size_t>(c)] != 0; };
    if (edge_support && l0 == Label::Edge && !near(up_[p], rho[p], rho, P, ring_feature) &&
        !near(down_[p], rho[p], rho, P, ring_feature))
      l = Label::Plane;
    if (P.inter_ring_roughness)
    {
      if (l == Label::Rough) l = Label::Plane;  // the window decides Rough
      if (share >= P.rough_window_fraction) l = Label::Rough;
    }
    // (a trunk's outline in front of foliage is a vertical line over rings, a leaf's is not)
    if (P.suppress_foliage_features && (l0 == Label::Edge || l0 == Label::Corner) &&
        share >= P.foliage_feature_fraction)
    {
      const auto outline = [&](std::int32_t c) { return silhouette(c, rho, P); };
      l = keep_silhouettes && outline(static_cast<std::int32_t>(p)) && stacked(p, rho, P, outline) ? l0 : Label::Rough;
    }
    if (P.occlusion_aware_jumps && l == Label::Corner)
    {
      // the far side of a jump: a ring neighbour is nearer by a jump (the occluder), whose side
      // the Corner moves to (the run's peak may have been on the far side)
      for (const std::int32_t q : {prev_[p], next_[p], twoBack(p), twoAhead(p)})
        if (q >= 0 && rho[q] < rho[p] && isJump(rho[q], rho[p], P))
        {
          occluder_[static_cast<std::size_t>(q)] = 1;
          l = Label::Plane;
          break;
        }
    }
    labels[p] = l;
  }
  if (P.occlusion_aware_jumps)
    for (std::uint32_t p = 0; p < m; ++p)
      if (occluder_[p] != 0 && (labels[p] == Label::Plane || labels[p] == Label::Edge)) labels[p] = Label::Corner;
  if (!P.thin_objects) return;
  thinRuns(g, P);
  for (std::uint32_t p = 0; p < m; ++p)
  {
    // (a Corner stays: the near side of the jump that bounds the run)
    if (labels[p] == Label::None || thin_[p] == 0 || labels[p] == Label::Corner) continue;
    if (stacked(p, rho, P, [this](std::int32_t c) { return thin_[static_cast<std::size_t>(c)] != 0; }))
      labels[p] = Label::Edge;
  }
}

bool InterRingRefiner::silhouette(std::int32_t p, const double* rho, const Params& P) const
{
  // a missing ring neighbour (no return) counts as farther, as in thinRuns
  for (const std::int32_t q : {prev_[static_cast<std::size_t>(p)], next_[static_cast<std::size_t>(p)]})
    if (q < 0 || (rho[q] > rho[p] && isJump(rho[q], rho[p], P))) return true;
  return false;
}


void InterRingRefiner::verticalNeighbours(const ScanGrid& g)
{
  const std::size_t m = g.size();
  up_.assign(m, -1);
  down_.assign(m, -1);
  if (g.up.size() != m) return;
  if (g.organized)
  {
    // a column is one firing: the same column one row up and down (beams may have azimuth offsets)
    const std::size_t width = g.num_input / static_cast<std::size_t>(std::max(g.num_rings, 1));
    for (std::uint32_t p = 0; p < m; ++p)
    {
      up_[p] = g.up[p];
      const std::uint32_t i = g.index[p];
      if (i >= width) down_[p] = g.grid_pos[i - width];
    }
    return;
  }
  const float tol = 1.5f * g.azimuth_resolution;
  const float* const az = g.azimuth.data();
  for (std::uint32_t p = 0; p < m; ++p)
    if (g.up[p] >= 0 && circularDistance(az[p] - az[g.up[p]]) <= tol) up_[p] = g.up[p];
  // the nearest sample on the ring below: both rings in azimuth order, walked together; q is
  // the last sample below at or before p's azimuth, the nearest is q or the one after it
  // (around the seam: the ring's last or first)
  for (int n = 1; n < g.num_rings; ++n)
  {
    const RingSpan R(g, n), B(g, n - 1);
    if (B.end() == B.b) continue;
    std::uint32_t q = B.b;
    for (std::uint32_t p = R.b; p < R.end(); ++p)
    {
      const float a = az[p];
      while (q + 1 < B.end() && az[q + 1] <= a) ++q;
      const std::uint32_t lo = az[q] <= a ? q : B.end() - 1, hi = q + 1 < B.end() && az[q] <= a ? q + 1 : B.b;
      const float d_lo = circularDistance(a - az[lo]), d_hi = circularDistance(az[hi] - a);
      const std::uint32_t best = d_hi < d_lo ? hi : lo;
      down_[p] = std::min(d_lo, d_hi) <= tol ? static_cast<std::int32_t>(best) : -1;
    }
  }
}

void InterRingRefiner::roughness(const ScanGrid& g, const Features& f, const Params& P)
{
  const std::size_t m = g.size();
  across_.resize(m);
  vert_.resize(m);
  ring_s_.resize(m);
  rough_.resize(m);
  acrossRings(m, up_.data(), down_.data(), g.range.data(), across_.data());
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
  win_total_.resize(m);
  win_rough_.resize(m);
  cum_.resize(m + 1);
  seg_end_.resize(m);
  for (std::int32_t n = 0; n < g.num_rings; ++n)
  {
    const RingSpan R(g, n);
    if (R.end() == R.b) continue;
    // inside the ring, a window is a stretch of the linked segment around p: prefix sums; within
    // h of the ring's ends (where a closed ring's window crosses the seam) and on a ring of at
    // most 2h + 1 samples (where the walks back and ahead meet), the links are walked
    cum_[R.b] = 0;
    for (std::uint32_t p = R.b; p < R.end(); ++p) cum_[p + 1] = cum_[p] + rough_[p];
    seg_end_[R.end() - 1] = R.end() - 1;
    for (std::uint32_t p = R.end() - 1; p > R.b; --p) seg_end_[p - 1] = g.linked[p] != 0 ? seg_end_[p] : p - 1;
    const bool short_ring = R.end() - R.b <= static_cast<std::uint32_t>(2 * h + 1);
    std::uint32_t seg_start = R.b;
    for (std::uint32_t p = R.b; p < R.end(); ++p)
    {
      if (p > R.b && g.linked[p] == 0) seg_start = p;
      if (!short_ring && p >= R.b + static_cast<std::uint32_t>(h) && p + static_cast<std::uint32_t>(h) < R.end())
      {
        const std::uint32_t lo = std::max(p - static_cast<std::uint32_t>(h), seg_start);
        const std::uint32_t hi = std::min(p + static_cast<std::uint32_t>(h), seg_end_[p]);
        win_total_[p] = static_cast<std::uint8_t>(hi - lo + 1);
        win_rough_[p] = static_cast<std::uint8_t>(cum_[hi + 1] - cum_[lo]);
        continue;
      }
      std::int32_t back[4];
      int nb = 0, total = 1, rough = rough_[p];
      for (std::int32_t q = prev_[p]; q >= 0 && q != static_cast<std::int32_t>(p) && nb < h;
           q = prev_[static_cast<std::size_t>(q)])
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
      win_total_[p] = static_cast<std::uint8_t>(total);
      win_rough_[p] = static_cast<std::uint8_t>(rough);
    }
  }
}

float InterRingRefiner::roughShare(std::uint32_t p, int rings) const
{
  int total = win_total_[p], rough = win_rough_[p];
  for (const std::vector<std::int32_t>* side : {&up_, &down_})
  {
    std::int32_t q = static_cast<std::int32_t>(p);
    for (int k = 0; k < rings && q >= 0; ++k)
    {
      q = (*side)[static_cast<std::size_t>(q)];
      if (q < 0) break;
      total += win_total_[static_cast<std::size_t>(q)];
      rough += win_rough_[static_cast<std::size_t>(q)];
    }
  }
  return total > 0 ? static_cast<float>(rough) / static_cast<float>(total) : 0.0f;
}


float InterRingRefiner::lowerQuartile(const std::vector<float>& values)
{
  // every 4th value: the quartile of a frame's 10^4-10^5 samples needs no more
  scratch_.clear();
  for (std::size_t i = 0; i < values.size(); i += 4)
    if (std::isfinite(values[i])) scratch_.push_back(values[i]);
  return scratch_.empty() ? 0.0f : selectNth(scratch_.data(), scratch_.size(), scratch_.size() / 4);
}

void InterRingRefiner::ringLinks(const ScanGrid& g)
{
  const std::size_t m = g.size();
  prev_.resize(m);
  next_.resize(m);
  for (std::int32_t n = 0; n < g.num_rings; ++n)
  {
    const RingSpan R(g, n);
    for (std::uint32_t p = R.b; p < R.end(); ++p)
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

void InterRingRefiner::thinRuns(const ScanGrid& g, const Params& P)
{
  const std::size_t m = g.size();
  const double* const rho = g.range.data();
  thin_.assign(m, 0);
  for (std::int32_t n = 0; n < g.num_rings; ++n)
  {
    const RingSpan R(g, n);
    // runs split at gaps and depth jumps; a run is thin when it is narrow and both samples
    // outside it are farther than all of it (no return counts as farther)
    // A closed ring's first and last runs meet at the seam: bounded there only by a jump
    // (a run that continues across the seam is never thin, e.g. a room's wall all around).
    const bool seam = R.closed && R.end() > R.b && g.linked[R.b] != 0;
    const bool seam_jump = seam && isJump(rho[R.b], rho[R.end() - 1], P);
    std::uint32_t s = R.b;
    while (s < R.end())
    {
      std::uint32_t t = s + 1;
      double rmax = rho[s];
      while (t < R.end() && g.linked[t] != 0 && !isJump(rho[t], rho[t - 1], P)) rmax = std::max(rmax, rho[t++]);
      const double across_seam_lo = seam_jump ? rho[R.end() - 1] : -kFar, across_seam_hi = seam_jump ? rho[R.b] : -kFar;
      const double lo = s > R.b ? (g.linked[s] != 0 ? rho[s - 1] : kFar) : (seam ? across_seam_lo : kFar);
      const double ro = t < R.end() ? (g.linked[t] != 0 ? rho[t] : kFar) : (seam ? across_seam_hi : kFar);
      const double dx = g.x[t - 1] - g.x[s], dy = g.y[t - 1] - g.y[s], dz = g.z[t - 1] - g.z[s];
      const bool narrow = dx * dx + dy * dy + dz * dz <= static_cast<double>(P.thin_max_width) * P.thin_max_width;
      const bool far_enough = rho[s] >= static_cast<double>(P.thin_min_range);  // (clutter at the sensor is not a pole)
      // in front of both sides; or, with thin_occluded, of one (the other, nearer, hides part of it)
      const bool in_front = P.thin_occluded ? (lo > rmax || ro > rmax) : (lo > rmax && ro > rmax);
      if (narrow && far_enough && in_front) std::fill(thin_.begin() + s, thin_.begin() + t, 1);
      s = t;
    }
  }
}

}  // namespace ring_curvature
