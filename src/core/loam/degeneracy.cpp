#include "loam/degeneracy.hpp"

#include "common/ring_index.hpp"

#include <Eigen/Eigenvalues>

#include <cmath>

namespace ring_curvature
{

namespace
{
// A neighbour farther than this is on another surface as often as not: no local direction.
constexpr double kMaxNeighbourDistance = 2.0;  // [m]

struct Vec
{
  double v[3];
  double norm() const { return std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]); }
};
Vec point(const ScanGrid& g, std::size_t p) { return {{g.x[p], g.y[p], g.z[p]}}; }
Vec sub(const Vec& a, const Vec& b) { return {{a.v[0] - b.v[0], a.v[1] - b.v[1], a.v[2] - b.v[2]}}; }
Vec cross(const Vec& a, const Vec& b)
{
  return {{a.v[1] * b.v[2] - a.v[2] * b.v[1], a.v[2] * b.v[0] - a.v[0] * b.v[2], a.v[0] * b.v[1] - a.v[1] * b.v[0]}};
}
bool normalize(Vec& a)
{
  const double l = a.norm();
  if (!(l > 1e-9)) return false;
  for (double& c : a.v) c /= l;
  return true;
}

/// Towards the nearest sample on the ring above, if near enough to lie on the same surface.
bool vertical(const ScanGrid& g, std::uint32_t p, Vec& d)
{
  const std::int32_t u = g.up[p];
  if (u < 0) return false;
  d = sub(point(g, static_cast<std::size_t>(u)), point(g, p));
  return d.norm() < kMaxNeighbourDistance && normalize(d);
}

// Samples each way along the ring for its direction: one sample's few centimetres would let
// range noise tilt the normal, and the tilt would read as information in every direction.
constexpr int kAlongSamples = 10;
constexpr std::size_t kMaxPlanes = 4000;

/// Along the ring through p: the chord between the linked samples kAlongSamples each way (fewer
/// at a gap).
bool along(const ScanGrid& g, const RingSpan& s, std::uint32_t p, Vec& t)
{
  const RingLinks links{g, s};
  std::uint32_t lo = p - s.b, hi = p - s.b;
  for (const bool back : {true, false})
    for (int i = 0; i < kAlongSamples; ++i)
    {
      std::uint32_t& end = back ? lo : hi;
      const std::int64_t q = back ? links.prev(end) : links.next(end);
      if (q < 0 || q == static_cast<std::int64_t>(s.b + (back ? hi : lo))) break;
      end = static_cast<std::uint32_t>(q - s.b);
    }
  if (lo == hi) return false;
  t = sub(point(g, s.b + hi), point(g, s.b + lo));
  return t.norm() < 2 * kMaxNeighbourDistance && normalize(t);
}
}  // namespace

void InformationMatrix::addRow(const double p[3], const double u[3])
{
  const double j[6] = {(p[1] * u[2] - p[2] * u[1]) * inv_length_, (p[2] * u[0] - p[0] * u[2]) * inv_length_,
                       (p[0] * u[1] - p[1] * u[0]) * inv_length_, u[0], u[1], u[2]};
  for (int r = 0; r < 6; ++r)
    for (int c = 0; c < 6; ++c) h_[static_cast<std::size_t>(r * 6 + c)] += j[r] * j[c];
  ++rows_;
}

void InformationMatrix::addPlane(const double p[3], const double n[3])
{
  addRow(p, n);
  ++planes_;
}

void InformationMatrix::addLine(const double p[3], const double d[3])
{
  // Two unit vectors across the line: d x (the axis least along d), then d x that.
  const int m = std::fabs(d[0]) <= std::fabs(d[1]) && std::fabs(d[0]) <= std::fabs(d[2]) ? 0 : (std::fabs(d[1]) <= std::fabs(d[2]) ? 1 : 2);
  Vec e{{0, 0, 0}};
  e.v[m] = 1;
  const Vec dv{{d[0], d[1], d[2]}};
  Vec u1 = cross(dv, e);
  normalize(u1);
  const Vec u2 = cross(dv, u1);
  addRow(p, u1.v);
  addRow(p, u2.v);
  ++lines_;
}

DegeneracyReport InformationMatrix::report(double min_eigenvalue) const
{
  DegeneracyReport r;
  r.plane_constraints = planes_;
  r.line_constraints = lines_;
  Eigen::Matrix<double, 6, 6> h;
  for (int i = 0; i < 36; ++i) h(i / 6, i % 6) = rows_ > 0 ? h_[static_cast<std::size_t>(i)] / rows_ : 0.0;
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix<double, 6, 6>> es(h);
  for (int i = 0; i < 6; ++i)
  {
    r.eigenvalues[static_cast<std::size_t>(i)] = es.eigenvalues()(i);
    r.weakest_direction[static_cast<std::size_t>(i)] = es.eigenvectors()(i, 0);
  }
  // Fewer rows than unknowns cannot pin the pose, whatever their directions.
  r.degenerate = rows_ < 6 || r.eigenvalues[0] < min_eigenvalue;
  return r;
}

DegeneracyReport assessDegeneracy(const ScanGrid& grid, const std::vector<Label>& labels, const LoamFeatures& features,
                                  const Params& params)
{
  InformationMatrix info(params.degeneracy_length);
  // Both sets are in ring order: follow the rings alongside.
  RingCursor ringOf{grid};
  // The matrix is an average over constraints: a few thousand planes estimate it as well as
  // the 30k of a 64-beam frame, at a fraction of the cost.
  const std::size_t stride = features.less_flat.size() / kMaxPlanes + 1;
  for (std::size_t i = 0; i < features.less_flat.size(); i += stride)
  {
    const std::uint32_t p = features.less_flat[i];
    const RingSpan s(grid, ringOf(p));
    Vec t, v;
    if (!along(grid, s, p, t) || !vertical(grid, p, v)) continue;
    Vec normal = cross(t, v);
    if (normal.norm() < 0.1) continue;  // the two directions within ~6 deg: no plane from them
    normalize(normal);
    info.addPlane(point(grid, p).v, normal.v);
  }
  // A line only where the sample above is a feature too (a pole, a wall's vertical edge): a crease
  // along the ring (a wall's foot) has no neighbour above on it, and its direction is unknown here.
  for (const std::uint32_t p : features.less_sharp)
  {
    Vec d;
    const std::int32_t u = grid.up[p];
    if (u < 0) continue;
    const Label lu = labels[static_cast<std::size_t>(u)];
    if ((lu == Label::Edge || lu == Label::Corner) && vertical(grid, p, d)) info.addLine(point(grid, p).v, d.v);
  }
  return info.report(params.degeneracy_min_eigenvalue);
}

}  // namespace ring_curvature
