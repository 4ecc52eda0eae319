// Inter-ring evidence on the ring-wise labels (see inter_ring.hpp).
#include "classification/inter_ring.hpp"

#include "common/ring_index.hpp"
#include "common/simd_clones.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>

namespace ring_curvature
{

namespace
{
constexpr double kFar = std::numeric_limits<double>::infinity();

// A depth jump between ranges r1 and r2.
inline bool isJump(double r1, double r2, const Params& P)
{
  return std::fabs(r1 - r2) > std::max(static_cast<double>(P.occlusion_min_jump),
                                       static_cast<double>(P.jump_min_ratio) * std::min(r1, r2));
}

// Where a run of samples ends: before a gap or a depth jump (1 at t: t - 1 and t are apart).
RC_SIMD_CLONES void runBreaks(std::size_t m, const std::uint8_t* __restrict linked, const double* __restrict rho,
                              const Params& P, std::uint8_t* __restrict out)
{
  for (std::size_t t = 1; t < m; ++t) out[t] = (linked[t] == 0) | isJump(rho[t], rho[t - 1], P);
}

// 1 where the label is Edge or Corner.
RC_SIMD_CLONES void featureFlags(std::size_t m, const Label* __restrict labels, std::uint8_t* __restrict out)
{
  for (std::size_t p = 0; p < m; ++p) out[p] = labels[p] == Label::Edge || labels[p] == Label::Corner ? 1 : 0;
}

// The near side of a jump whose far side was a Corner: Corner, unless Rough (foliage) or None.
RC_SIMD_CLONES void occluderCorners(std::size_t m, const std::uint8_t* __restrict occluder, Label* __restrict labels)
{
  for (std::size_t p = 0; p < m; ++p)
  {
    const Label l = labels[p];
    labels[p] = occluder[p] != 0 && (l == Label::Plane || l == Label::Edge) ? Label::Corner : l;
  }
}

// The first position at or after p (m if none) whose flag is set; flags are mostly 0, so whole
// words of them are skipped at once.
inline std::size_t nextFlagged(const std::uint8_t* flags, std::size_t p, std::size_t m)
{
  for (std::uint64_t w = 0; p + 8 <= m; p += 8)
  {
    std::memcpy(&w, flags + p, 8);
    if (w != 0) break;
  }
  while (p < m && flags[p] == 0) ++p;
  return p;
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
  // each sample reads and writes only its own label, and no step makes a label None or moves
  // one between {Plane, Rough} and {Edge, Corner} but occlusion's (set after the pass): Plane
  // and Rough are decided by the window alone, in a pass of their own
  if (share_needed)
  {
    roughness(g, f, P);
    shares(window_rings, P, labels);
  }
  refineFeatures(g, P, share_needed, labels);
  if (!P.thin_objects) return;
  thinRuns(g, P);
  const double* const rho = g.range.data();
  for (std::size_t i = nextFlagged(thin_.data(), 0, m); i < m; i = nextFlagged(thin_.data(), i + 1, m))
  {
    const auto p = static_cast<std::uint32_t>(i);
    // (a Corner stays: the near side of the jump that bounds the run)
    if (labels[p] == Label::None || labels[p] == Label::Corner) continue;
    if (stacked(p, rho, P, [this](std::int32_t c) { return thin_[static_cast<std::size_t>(c)] != 0; }))
      labels[p] = Label::Edge;
  }
}

void InterRingRefiner::refineFeatures(const ScanGrid& g, const Params& P, bool share_needed, std::vector<Label>& labels)
{
  const std::size_t m = g.size();
  const bool keep_silhouettes = P.suppress_foliage_features && P.foliage_keep_silhouettes;
  // a Corner moved to the near side of its jump is marked in occluder_ and set after the pass
  const double* const rho = g.range.data();
  if (P.occlusion_aware_jumps) occluder_.assign(m, 0);
  const bool edge_support = P.edge_vertical_support && (!share_needed || noise_sigma_ > P.edge_support_noise);
  // the steps below concern only the few Edges and Corners (and read them as they were)
  ring_feature_.resize(m);
  featureFlags(m, labels.data(), ring_feature_.data());
  const std::uint8_t* const features = ring_feature_.data();
  for (std::size_t i = nextFlagged(features, 0, m); i < m; i = nextFlagged(features, i + 1, m))
  {
    const auto p = static_cast<std::uint32_t>(i);
    const Label l0 = labels[p];
    Label l = l0;
    const float share = share_needed ? share_[p] : 0.0f;
    // a crease crosses rings, range noise does not line up from one ring to the next; asked only
    // of a noisy frame (a fold along the ring, e.g. a wall's foot, has no Edge on the rings beside
    // it, and a quiet sensor's ring-wise Edges are reliable)
    const auto ring_feature = [this](std::int32_t c) { return ring_feature_[static_cast<std::size_t>(c)] != 0; };
    if (edge_support && l0 == Label::Edge && !near(up_[p], rho[p], rho, P, ring_feature) &&
        !near(down_[p], rho[p], rho, P, ring_feature))
      l = Label::Plane;
    if (P.inter_ring_roughness && share >= P.rough_window_fraction) l = Label::Rough;
    // (a trunk's outline in front of foliage is a vertical line over rings, a leaf's is not)
    if (P.suppress_foliage_features && share >= P.foliage_feature_fraction)
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
  if (P.occlusion_aware_jumps) occluderCorners(m, occluder_.data(), labels.data());
}

bool InterRingRefiner::silhouette(std::int32_t p, const double* rho, const Params& P) const
{
  // a missing ring neighbour (no return) counts as farther, as in thinRuns
  for (const std::int32_t q : {prev_[static_cast<std::size_t>(p)], next_[static_cast<std::size_t>(p)]})
    if (q < 0 || (rho[q] > rho[p] && isJump(rho[q], rho[p], P))) return true;
  return false;
}


void InterRingRefiner::thinRuns(const ScanGrid& g, const Params& P)
{
  const std::size_t m = g.size();
  const double* const rho = g.range.data();
  thin_.assign(m, 0);
  run_break_.resize(m);
  run_break_[0] = 1;
  runBreaks(m, g.linked.data(), rho, P, run_break_.data());
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
      while (t < R.end() && run_break_[t] == 0) ++t;
      const double dx = g.x[t - 1] - g.x[s], dy = g.y[t - 1] - g.y[s], dz = g.z[t - 1] - g.z[s];
      const bool narrow = dx * dx + dy * dy + dz * dz <= static_cast<double>(P.thin_max_width) * P.thin_max_width;
      const bool far_enough = rho[s] >= static_cast<double>(P.thin_min_range);  // (clutter at the sensor is not a pole)
      if (narrow && far_enough)
      {
        const double across_seam_lo = seam_jump ? rho[R.end() - 1] : -kFar, across_seam_hi = seam_jump ? rho[R.b] : -kFar;
        const double lo = s > R.b ? (g.linked[s] != 0 ? rho[s - 1] : kFar) : (seam ? across_seam_lo : kFar);
        const double ro = t < R.end() ? (g.linked[t] != 0 ? rho[t] : kFar) : (seam ? across_seam_hi : kFar);
        const double rmax = *std::max_element(rho + s, rho + t);  // (only for the few narrow runs)
        // in front of both sides; or, with thin_occluded, of one (the other, nearer, hides part of it)
        const bool in_front = P.thin_occluded ? (lo > rmax || ro > rmax) : (lo > rmax && ro > rmax);
        if (in_front) std::fill(thin_.begin() + s, thin_.begin() + t, 1);
      }
      s = t;
    }
  }
}

}  // namespace ring_curvature
