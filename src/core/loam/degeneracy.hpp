// How well a frame's LOAM features pin down the six degrees of freedom of the scan-to-map match:
// the information matrix of their point-to-plane and point-to-line constraints. A corridor or a
// tunnel leaves the motion along its axis unconstrained; LOAM-family odometry then slides.
#pragma once

#include "ring_curvature/loam_features.hpp"
#include "ring_curvature/params.hpp"
#include "ring_curvature/scan_grid.hpp"

#include <array>
#include <vector>

namespace ring_curvature
{

/// Accumulates constraint rows J = [(p x u) / length, u] (rotation as metres at `length`).
class InformationMatrix
{
public:
  explicit InformationMatrix(double length) : inv_length_(1.0 / length) {}
  /// A point p on a plane of unit normal n: one row.
  void addPlane(const double p[3], const double n[3]);
  /// A point p on a line of unit direction d: the two rows across the line.
  void addLine(const double p[3], const double d[3]);
  /// Eigen-decomposes the matrix divided by its number of rows.
  DegeneracyReport report(double min_eigenvalue) const;

private:
  void addRow(const double p[3], const double u[3]);
  std::array<double, 36> h_{};
  double inv_length_;
  std::uint32_t planes_ = 0, lines_ = 0, rows_ = 0;
};

/// Planes from the less flat points, lines from the less sharp ones whose sample above is an
/// Edge/Corner too. Directions come from the ring (5 samples each way) and the ring above.
DegeneracyReport assessDegeneracy(const ScanGrid& grid, const std::vector<Label>& labels, const LoamFeatures& features,
                                  const Params& params);

}  // namespace ring_curvature
