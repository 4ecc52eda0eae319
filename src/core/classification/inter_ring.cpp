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

// Rough samples (both measures above their bounds), and each sample's 5-sample window along its
// ring: how many samples it has (high nibble), how many of them rough (low nibble).
RC_SIMD_CLONES void roughWindows(std::size_t m, const std::int32_t* __restrict prev,
                                 const std::int32_t* __restrict next, const float* __restrict vert,
                                 const float* __restrict ring_s, float v_thr, float s_thr,
                                 std::uint8_t* __restrict rough, std::uint8_t* __restrict window)
{
  for (std::size_t p = 0; p < m; ++p) rough[p] = (ring_s[p] > s_thr) & (vert[p] > v_thr);
  for (std::size_t p = 0; p < m; ++p)
  {
    const auto self = static_cast<std::int32_t>(p);
    const std::int32_t a = prev[p], c = next[p];
    const std::int32_t a2 = a >= 0 ? prev[a] : -1, c2 = c >= 0 ? next[c] : -1;
    int total = 1, count = rough[p];
    for (const std::int32_t q : {a, c, a2 != self ? a2 : -1, c2 != self ? c2 : -1})
    {
      total += q >= 0 ? 1 : 0;
      count += q >= 0 ? rough[q] : 0;
    }
    window[p] = static_cast<std::uint8_t>(total << 4 | count);
  }
}
}  // namespace

bool InterRingRefiner::enabled(const Params& P)
{
  // Algorithm 1 (quartile mode) stays as the paper wrote it
  return P.classifier_mode == ClassifierMode::Robust &&
         (P.inter_ring_roughness || P.suppress_foliage_features || P.occlusion_aware_jumps || P.thin_objects);
}

void InterRingRefiner::refine(const ScanGrid& g, const Features& f, const Params& P, std::vector<Label>& labels)
{
  const std::size_t m = g.size();
  if (m == 0 || !enabled(P)) return;
  ringLinks(g);
  verticalNeighbours(g);
  const bool share_needed = P.inter_ring_roughness || P.suppress_foliage_features;
  if (share_needed) roughness(g, f, P);
  // in place: each sample reads and writes only its own label (no step makes a label None)
  const double* const rho = g.range.data();
  for (std::uint32_t p = 0; p < m; ++p)
  {
    const Label l0 = labels[p];
    if (l0 == Label::None) continue;
    Label l = l0;
    const float share = share_needed ? roughShare(p) : 0.0f;
    if (P.inter_ring_roughness)
    {
      if (l0 == Label::Rough) l = Label::Plane;  // the window decides Rough
      if (share >= P.rough_window_fraction) l = Label::Rough;
    }
    if (P.suppress_foliage_features && (l == Label::Edge || l == Label::Corner) &&
        share >= P.foliage_feature_fraction)
      l = Label::Rough;
    if (P.occlusion_aware_jumps && l == Label::Corner)
    {
      // the far side of a jump: a ring neighbour is nearer by a jump (the occluder)
      bool shadow = false;
      for (const std::int32_t q : {prev_[p], next_[p], twoBack(p), twoAhead(p)})
        shadow = shadow || (q >= 0 && rho[q] < rho[p] && isJump(rho[q], rho[p], P));
      if (shadow) l = Label::Plane;
    }
    labels[p] = l;
  }
  if (!P.thin_objects) return;
  thinRuns(g, P);
  for (std::uint32_t p = 0; p < m; ++p)
  {
    // (a Corner stays: the near side of the jump that bounds the run)
    if (labels[p] == Label::None || thin_[p] == 0 || labels[p] == Label::Corner) continue;
    const std::int32_t u = up_[p], d = down_[p];
    int stacked = 0;
    for (const std::int32_t q : {u, d, u >= 0 ? up_[static_cast<std::size_t>(u)] : -1,
                                 d >= 0 ? down_[static_cast<std::size_t>(d)] : -1})
      stacked += q >= 0 && thin_[static_cast<std::size_t>(q)] != 0 &&
                         std::fabs(rho[q] - rho[p]) < static_cast<double>(P.thin_max_range_step)
                     ? 1
                     : 0;
    if (stacked >= P.thin_min_stack) labels[p] = Label::Edge;
  }
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
  window_.resize(m);
  acrossRings(m, up_.data(), down_.data(), g.range.data(), across_.data());
  scaledRoughness(m, prev_.data(), next_.data(), across_.data(), f.smoothness.data(), g.range.data(),
                  P.rough_range_scale, vert_.data(), ring_s_.data());
  // The bounds follow the frame's own noise: a multiple of the lower quartile of each measure
  // (most samples are planes, and foliage rarely reaches the lower quartile), never below the
  // fixed minimum that a quiet sensor needs.
  const float v_thr = std::max(P.rough_vertical_min, P.rough_noise_k * lowerQuartile(vert_));
  const float s_thr = std::max(P.rough_smoothness_min, P.rough_noise_k * P.rough_noise_k * lowerQuartile(ring_s_));
  roughWindows(m, prev_.data(), next_.data(), vert_.data(), ring_s_.data(), v_thr, s_thr, rough_.data(),
               window_.data());
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
      if (narrow && far_enough && lo > rmax && ro > rmax) std::fill(thin_.begin() + s, thin_.begin() + t, 1);
      s = t;
    }
  }
}

}  // namespace ring_curvature
