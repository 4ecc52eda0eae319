// LOAM's four feature sets (sharp, less sharp, flat, less flat) chosen from the core's labels
// and scores, each point's time in the sweep, and how well the chosen features pin down the pose.
// What LOAM-family odometry (A-LOAM, F-LOAM, LeGO-LOAM's mapping) takes as input.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

namespace ring_curvature
{

/// The 6x6 information matrix of the frame's point-to-plane and point-to-line constraints, in
/// the pose increment (rotation about x, y, z scaled to metres at `degeneracy_length`, then
/// translation x, y, z), divided by the number of constraint rows.
struct DegeneracyReport
{
  std::uint32_t plane_constraints = 0, line_constraints = 0;
  std::array<double, 6> eigenvalues{};        ///< ascending
  std::array<double, 6> weakest_direction{};  ///< unit eigenvector of eigenvalues[0]
  bool degenerate = false;                    ///< eigenvalues[0] < degeneracy_min_eigenvalue
};

/// Grid positions (ScanGrid order: ring by ring, azimuth order within a ring) of each set.
struct LoamFeatures
{
  std::vector<std::uint32_t> sharp;       ///< sharpest Edge/Corner points per ring sector
  std::vector<std::uint32_t> less_sharp;  ///< more of them (holds `sharp`)
  std::vector<std::uint32_t> flat;        ///< flattest Plane points per ring sector
  std::vector<std::uint32_t> less_flat;   ///< Plane points, one per voxel per ring (holds `flat`)
  /// Per grid position: seconds since the sweep began, in [0, scan_period]. From the input's
  /// time field when it varies over the frame, else from the azimuth turned since the first point.
  std::vector<float> sweep_time;
  bool time_from_field = false;
  /// With time_from_field: the first point's time as the field gives it, in seconds (relative to
  /// the header stamp for most drivers, absolute for Hesai and RoboSense).
  double first_time = 0.0;
  DegeneracyReport degeneracy;
};

}  // namespace ring_curvature
