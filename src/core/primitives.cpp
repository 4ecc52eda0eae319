// Section 4.3: union-find over the scan grid (angular and vertical neighbours, same label,
// proximity by Eq 19-20), then one pass of moments per component. Linear time, no recursion.
#include "ring_curvature/primitives.hpp"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>

namespace ring_curvature
{

namespace
{
constexpr float kPi = 3.14159265358979f;
inline float angDiff(float a, float b)
{
  float d = std::fabs(a - b);
  return d > kPi ? 2 * kPi - d : d;
}
}  // namespace

// inline: only extract() calls these, and out of line each call went through the shared
// library's PLT (perf showed find@plt).
inline std::uint32_t PrimitiveExtractor::find(std::uint32_t a)
{
  while (parent_[a] != a)
  {
    parent_[a] = parent_[parent_[a]];  // path halving
    a = parent_[a];
  }
  return a;
}

inline void PrimitiveExtractor::unite(std::uint32_t a, std::uint32_t b)
{
  a = find(a);
  b = find(b);
  if (a == b) return;
  if (a < b) std::swap(a, b);
  parent_[a] = b;  // the smaller position is the root: components are numbered in scan order
}

void PrimitiveExtractor::extract(const ScanGrid& g, const std::vector<Label>& labels, const Params& P,
                                 PrimitiveSet& out)
{
  const std::size_t m = g.size();
  out.primitives.clear();
  out.indices.clear();
  out.of_grid.assign(m, -1);
  parent_.resize(m);
  for (std::size_t p = 0; p < m; ++p) parent_[p] = static_cast<std::uint32_t>(p);
  ring_of_pos_.resize(m);
  for (int n = 0; n < g.num_rings; ++n)
    std::fill(ring_of_pos_.begin() + g.ring_begin[static_cast<std::size_t>(n)],
              ring_of_pos_.begin() + g.ring_begin[static_cast<std::size_t>(n) + 1], static_cast<std::uint16_t>(n));

  // a table: this is asked once or more per grid position in every loop below
  const bool want[kNumLabels] = {false, true, true, true, P.rough_primitives};
  static_assert(static_cast<int>(Label::Plane) == 1 && static_cast<int>(Label::Edge) == 2 &&
                    static_cast<int>(Label::Corner) == 3 && static_cast<int>(Label::Rough) == 4,
                "want[] is indexed by Label");
  auto wanted = [&](Label l) { return want[static_cast<std::size_t>(l)]; };
  const float az_tol = P.proximity_azimuth_factor * g.azimuth_resolution;  // Eq 19
  auto close = [&](std::uint32_t a, std::uint32_t b, bool check_azimuth) {
    const double ra = g.range[a], rb = g.range[b];
    const double rho_tol = std::max(P.proximity_range_ratio * 0.5 * (ra + rb), static_cast<double>(P.proximity_range_min));  // Eq 20
    if (std::fabs(ra - rb) > rho_tol) return false;
    return !check_azimuth || angDiff(g.azimuth[a], g.azimuth[b]) <= az_tol;
  };

  for (int n = 0; n < g.num_rings; ++n)
  {
    const std::uint32_t b = g.ring_begin[static_cast<std::size_t>(n)], e = g.ring_begin[static_cast<std::size_t>(n) + 1];
    for (std::uint32_t p = b; p < e; ++p)
    {
      const Label l = labels[p];
      if (!wanted(l)) continue;
      // angular neighbour (n, k+1 mod K)
      const std::uint32_t nx = p + 1 < e ? p + 1 : b;
      if (nx != p && g.linked[nx] && labels[nx] == l && close(p, nx, true)) unite(p, nx);
      // vertical neighbour (n+1, k): the nearest sample in azimuth, or one beside it, within Eq 19
      const std::int32_t u = g.up.empty() ? -1 : g.up[p];
      if (u < 0) continue;
      const std::uint32_t uu = static_cast<std::uint32_t>(u);
      const std::uint32_t ub = g.ring_begin[static_cast<std::size_t>(n) + 1], ue = g.ring_begin[static_cast<std::size_t>(n) + 2];
      const std::uint32_t cand[3] = {uu, uu > ub ? uu - 1 : ue - 1, uu + 1 < ue ? uu + 1 : ub};
      for (std::uint32_t q : cand)
      {
        // organized clouds: a column is one firing, beams may have their own azimuth offsets
        if (labels[q] == l && close(p, q, !g.organized || q != uu))
        {
          unite(p, q);
          break;
        }
      }
    }
  }

  // A root is the smallest position of its component (see unite) and path halving keeps
  // parent_[p] <= p, so one forward pass points every position straight at its root: the
  // look-ups below are then a load instead of a find() each.
  // Component sizes (in the same pass), then ids for the large-enough ones in scan order.
  fill_.assign(m, 0);  // size per root
  for (std::size_t p = 0; p < m; ++p)
  {
    parent_[p] = parent_[parent_[p]];
    if (wanted(labels[p])) ++fill_[parent_[p]];
  }
  // duplicates (same firing, same range) join their representative's primitive
  for (const std::uint32_t i : g.duplicates)
    if (wanted(labels[static_cast<std::size_t>(g.grid_pos[i])])) ++fill_[parent_[static_cast<std::size_t>(g.grid_pos[i])]];
  std::uint32_t total = 0;
  // root_to_prim_ is only read at the roots of wanted positions, so only those are written
  root_to_prim_.resize(m);
  for (std::size_t p = 0; p < m; ++p)
  {
    if (!wanted(labels[p]) || parent_[p] != p) continue;
    if (fill_[p] < static_cast<std::uint32_t>(P.min_primitive_points))
    {
      root_to_prim_[p] = -1;
      continue;
    }
    PrimitiveInfo prim;
    prim.id = static_cast<std::uint32_t>(out.primitives.size());
    prim.label = labels[p];
    prim.first = total;
    total += fill_[p];
    root_to_prim_[p] = static_cast<std::int32_t>(prim.id);
    out.primitives.push_back(prim);
  }
  out.indices.resize(total);
  for (auto& prim : out.primitives) prim.num_points = 0;  // used as the fill cursor below

  auto addPoint = [&](std::int32_t id, std::uint32_t input_index, std::uint32_t pos) {
    PrimitiveInfo& pr = out.primitives[static_cast<std::size_t>(id)];
    out.indices[pr.first + pr.num_points++] = input_index;
    const Eigen::Vector3f v(static_cast<float>(g.x[pos]), static_cast<float>(g.y[pos]), static_cast<float>(g.z[pos]));
    if (pr.num_points == 1)
    {
      pr.bbox_min = pr.bbox_max = v;
      pr.ring_min = pr.ring_max = ring_of_pos_[pos];
    }
    else
    {
      pr.bbox_min = pr.bbox_min.cwiseMin(v);
      pr.bbox_max = pr.bbox_max.cwiseMax(v);
      pr.ring_min = std::min(pr.ring_min, ring_of_pos_[pos]);
      pr.ring_max = std::max(pr.ring_max, ring_of_pos_[pos]);
    }
    pr.centroid += v;  // sum for now
  };
  for (std::size_t p = 0; p < m; ++p)
  {
    if (!wanted(labels[p])) continue;
    const std::int32_t id = root_to_prim_[parent_[p]];
    out.of_grid[p] = id;
    if (id >= 0) addPoint(id, g.index[p], static_cast<std::uint32_t>(p));
  }
  for (const std::uint32_t i : g.duplicates)
  {
    const std::int32_t id = out.of_grid[static_cast<std::size_t>(g.grid_pos[i])];
    if (id >= 0) addPoint(id, i, static_cast<std::uint32_t>(g.grid_pos[i]));
  }
  for (auto& pr : out.primitives) pr.centroid /= static_cast<float>(pr.num_points);

  // Second moments about the centroids, accumulated in grid order (a sequential read) rather
  // than primitive by primitive through `indices` (a random read per point). Each primitive
  // still sums its points in the order of its indices (grid order, then duplicates in input
  // order), so the sums are bit for bit the same.
  cov_.resize(out.primitives.size());
  centre_.resize(out.primitives.size());
  for (std::size_t j = 0; j < out.primitives.size(); ++j)
  {
    cov_[j].setZero();
    centre_[j] = out.primitives[j].centroid.cast<double>();
  }
  auto addMoment = [&](std::int32_t id, std::size_t pos) {
    const Eigen::Vector3d& c = centre_[static_cast<std::size_t>(id)];
    const Eigen::Vector3d d(g.x[pos] - c.x(), g.y[pos] - c.y(), g.z[pos] - c.z());
    cov_[static_cast<std::size_t>(id)].noalias() += d * d.transpose();
  };
  for (std::size_t p = 0; p < m; ++p)
    if (out.of_grid[p] >= 0) addMoment(out.of_grid[p], p);
  for (const std::uint32_t i : g.duplicates)
  {
    const auto pos = static_cast<std::size_t>(g.grid_pos[i]);
    if (out.of_grid[pos] >= 0) addMoment(out.of_grid[pos], pos);
  }
  for (auto& pr : out.primitives)
  {
    Eigen::Matrix3d& cov = cov_[pr.id];
    const Eigen::Vector3d& c = centre_[pr.id];
    cov /= static_cast<double>(pr.num_points);
    Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> es;
    es.computeDirect(cov);
    const Eigen::Vector3d ev = es.eigenvalues().cwiseMax(0.0);  // ascending
    pr.eigenvalues = ev.cast<float>();
    if (pr.label == Label::Plane)
    {
      Eigen::Vector3d nrm = es.eigenvectors().col(0);
      if (nrm.dot(c) > 0) nrm = -nrm;  // face the sensor
      pr.axis = nrm.cast<float>();
      pr.rms_error = static_cast<float>(std::sqrt(ev(0)));
    }
    else
    {
      pr.axis = es.eigenvectors().col(2).cast<float>();
      pr.rms_error = static_cast<float>(std::sqrt(ev(0) + ev(1)));
    }
  }
}

}  // namespace ring_curvature
