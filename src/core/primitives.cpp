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
  // Raw pointers and parameters in locals, read once: through the vectors and P the compiler
  // reloaded data pointers and parameters inside the loops below (perf annotate), as it may not
  // prove that the stores to parent_ / fill_ / the primitives leave them unchanged.
  const double* const range = g.range.data();
  const float* const azimuth = g.azimuth.data();
  const Label* const lab = labels.data();
  const std::uint8_t* const linked = g.linked.data();
  const double range_ratio = P.proximity_range_ratio;
  const double range_min = static_cast<double>(P.proximity_range_min);
  auto close = [&](std::uint32_t a, std::uint32_t b, bool check_azimuth) {
    const double ra = range[a], rb = range[b];
    const double rho_tol = std::max(range_ratio * 0.5 * (ra + rb), range_min);  // Eq 20
    if (std::fabs(ra - rb) > rho_tol) return false;
    return !check_azimuth || angDiff(azimuth[a], azimuth[b]) <= az_tol;
  };

  for (int n = 0; n < g.num_rings; ++n)
  {
    const std::uint32_t b = g.ring_begin[static_cast<std::size_t>(n)], e = g.ring_begin[static_cast<std::size_t>(n) + 1];
    for (std::uint32_t p = b; p < e; ++p)
    {
      const Label l = lab[p];
      if (!wanted(l)) continue;
      // angular neighbour (n, k+1 mod K)
      const std::uint32_t nx = p + 1 < e ? p + 1 : b;
      if (nx != p && linked[nx] && lab[nx] == l && close(p, nx, true)) unite(p, nx);
      // vertical neighbour (n+1, k): the nearest sample in azimuth, or one beside it, within Eq 19
      const std::int32_t u = g.up.empty() ? -1 : g.up[p];
      if (u < 0) continue;
      const std::uint32_t uu = static_cast<std::uint32_t>(u);
      const std::uint32_t ub = g.ring_begin[static_cast<std::size_t>(n) + 1], ue = g.ring_begin[static_cast<std::size_t>(n) + 2];
      const std::uint32_t cand[3] = {uu, uu > ub ? uu - 1 : ue - 1, uu + 1 < ue ? uu + 1 : ub};
      for (std::uint32_t q : cand)
      {
        // organized clouds: a column is one firing, beams may have their own azimuth offsets
        if (lab[q] == l && close(p, q, !g.organized || q != uu))
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
  std::uint32_t* const parent = parent_.data();  // raw pointers: see `range` above
  std::uint32_t* const fill = fill_.data();
  const std::int32_t* const grid_pos = g.grid_pos.data();
  for (std::size_t p = 0; p < m; ++p)
  {
    parent[p] = parent[parent[p]];
    if (wanted(lab[p])) ++fill[parent[p]];
  }
  // duplicates (same firing, same range) join their representative's primitive
  for (const std::uint32_t i : g.duplicates)
    if (wanted(lab[static_cast<std::size_t>(grid_pos[i])])) ++fill[parent[static_cast<std::size_t>(grid_pos[i])]];
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

  PrimitiveInfo* const prims = out.primitives.data();
  std::uint32_t* const indices = out.indices.data();
  const std::uint16_t* const ring_of_pos = ring_of_pos_.data();
  const double* const gx = g.x.data();
  const double* const gy = g.y.data();
  const double* const gz = g.z.data();
  auto addPoint = [&](std::int32_t id, std::uint32_t input_index, std::uint32_t pos) {
    PrimitiveInfo& pr = prims[static_cast<std::size_t>(id)];
    indices[pr.first + pr.num_points++] = input_index;
    const Eigen::Vector3f v(static_cast<float>(gx[pos]), static_cast<float>(gy[pos]), static_cast<float>(gz[pos]));
    if (pr.num_points == 1)
    {
      pr.bbox_min = pr.bbox_max = v;
      pr.ring_min = pr.ring_max = ring_of_pos[pos];
    }
    else
    {
      pr.bbox_min = pr.bbox_min.cwiseMin(v);
      pr.bbox_max = pr.bbox_max.cwiseMax(v);
      pr.ring_min = std::min(pr.ring_min, ring_of_pos[pos]);
      pr.ring_max = std::max(pr.ring_max, ring_of_pos[pos]);
    }
    pr.centroid += v;  // sum for now
  };
  {
    const std::int32_t* const root_to_prim = root_to_prim_.data();
    std::int32_t* const of_grid_out = out.of_grid.data();
    const std::uint32_t* const index = g.index.data();
    for (std::size_t p = 0; p < m; ++p)
    {
      if (!wanted(lab[p])) continue;
      const std::int32_t id = root_to_prim[parent[p]];
      of_grid_out[p] = id;
      if (id >= 0) addPoint(id, index[p], static_cast<std::uint32_t>(p));
    }
    for (const std::uint32_t i : g.duplicates)
    {
      const std::int32_t id = of_grid_out[static_cast<std::size_t>(grid_pos[i])];
      if (id >= 0) addPoint(id, i, static_cast<std::uint32_t>(grid_pos[i]));
    }
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
  // Only the lower triangle is summed: the outer product d d^T is symmetric (d_i d_j and d_j d_i
  // are the same double), so the upper triangle is a copy of it, made once per primitive below
  // instead of three more multiply-adds per point. The entries are bit for bit those of
  // `cov += d * d.transpose()`.
  const std::int32_t* const of_grid = out.of_grid.data();
  Eigen::Matrix3d* const cov_data = cov_.data();
  const Eigen::Vector3d* const centre_data = centre_.data();
  auto addMoment = [&](std::int32_t id, std::size_t pos) {
    const Eigen::Vector3d& c = centre_data[static_cast<std::size_t>(id)];
    const double dx = gx[pos] - c.x(), dy = gy[pos] - c.y(), dz = gz[pos] - c.z();
    Eigen::Matrix3d& M = cov_data[static_cast<std::size_t>(id)];
    M(0, 0) += dx * dx;
    M(1, 0) += dy * dx;
    M(2, 0) += dz * dx;
    M(1, 1) += dy * dy;
    M(2, 1) += dz * dy;
    M(2, 2) += dz * dz;
  };
  for (std::size_t p = 0; p < m; ++p)
    if (of_grid[p] >= 0) addMoment(of_grid[p], p);
  for (const std::uint32_t i : g.duplicates)
  {
    const auto pos = static_cast<std::size_t>(g.grid_pos[i]);
    if (of_grid[pos] >= 0) addMoment(of_grid[pos], pos);
  }
  for (auto& pr : out.primitives)
  {
    Eigen::Matrix3d& cov = cov_[pr.id];
    cov(0, 1) = cov(1, 0);
    cov(0, 2) = cov(2, 0);
    cov(1, 2) = cov(2, 1);
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
