// The union-find steps of the primitive extraction over the scan grid: each ring cut into runs of
// neighbours that join (Eq 19-20, same wanted label), and the runs of neighbouring rings united.
#pragma once

#include "primitives/primitive_extractor.hpp"

#include <cstddef>
#include <cstdint>

namespace ring_curvature
{
namespace detail
{

/// Root of run a, halving the path on the way.
inline std::uint32_t find(std::uint32_t* parent, std::uint32_t a)
{
  while (parent[a] != a)
  {
    parent[a] = parent[parent[a]];  // path halving
    a = parent[a];
  }
  return a;
}

/// Unites the components of runs a and b; the smaller run id is the root, so that components
/// are numbered in scan order.
inline void unite(std::uint32_t* parent, std::uint32_t a, std::uint32_t b)
{
  a = find(parent, a);
  b = find(parent, b);
  if (a == b) return;
  if (a < b) std::swap(a, b);
  parent[a] = b;
}

/// The inputs of the vertical unions of one ring (n-1) with the ring above it (n).
struct VerticalRing
{
  std::uint32_t b, e;  // the ring above: [b, e)
  const PrimitiveExtractor::Run* __restrict runs;
  const Label* __restrict lab;
  const std::int32_t* __restrict up;
  const double* __restrict range;
  const float* __restrict azimuth;
  bool organized;
  double half_ratio, range_min;  // inRange's range_ratio * 0.5 * (ra + rb), left to right
  float az_tol;
  const std::uint32_t* __restrict run;
  std::uint32_t* parent;
};

/// Which positions (b, e) of a ring join their predecessor's run: same wanted label (labels 1 to
/// num_wanted), linked, and close by Eq 19-20.
void angularJoins(std::size_t b, std::size_t e, const Label* lab, const std::uint8_t* linked, const double* range,
                  const float* azimuth, std::uint8_t num_wanted, double range_ratio, double range_min, float az_tol,
                  std::uint8_t* join);

/// Cuts ring [b, e) into runs from join[]; returns the new number of listed runs.
std::size_t cutRing(std::uint32_t b, std::uint32_t e, const Label* lab, const std::uint8_t* join, const bool* want,
                    std::uint32_t none, std::uint32_t* parent, std::uint32_t* run, std::int32_t* comp,
                    PrimitiveExtractor::Run* runs, std::size_t num_runs);

/// Unites the runs [k0, k1) of ring n-1 with the runs of ring n they touch (Eq 19-20).
void verticalUnions(const VerticalRing& V, std::uint32_t k0, std::uint32_t k1, std::uint32_t none);

}  // namespace detail
}  // namespace ring_curvature
