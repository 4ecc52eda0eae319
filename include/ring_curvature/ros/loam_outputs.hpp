// The LOAM outputs (~loam/cloud, ~loam/sharp, ~loam/less_sharp, ~loam/flat, ~loam/less_flat):
// clouds sorted by ring in the layout LOAM-family back ends read (A-LOAM's scanRegistration
// output), or in the input's own layout.
#pragma once

#include <sensor_msgs/PointCloud2.h>

#include <cstdint>
#include <vector>

#include "ring_curvature/loam_features.hpp"
#include "ring_curvature/params.hpp"
#include "ring_curvature/scan_grid.hpp"
#include "ring_curvature/sweep_deskew.hpp"

namespace ring_curvature
{

/// Byte layout of pcl::PointXYZI (x, y, z, pad, intensity, pad x3): what pcl::fromROSMsg maps.
constexpr std::uint32_t kXyziPointStep = 32;
constexpr std::uint32_t kXyziIntensityOffset = 16;

/// New unorganized cloud of the grid positions `positions` (in ring order; all of the grid when
/// null), with the input's header. Xyzi: x, y, z and intensity = ring + seconds since the sweep
/// began (LOAM's "scanID + scanPeriod * relTime"). Input: each point's input record, every field.
/// Xyzi with `deskew`: x, y, z moved to the sensor frame at the deskew's reference time (the stamp).
/// (`reuse` as for makeLabelledCloud.)
sensor_msgs::PointCloud2Ptr makeLoamCloud(const sensor_msgs::PointCloud2& input, const ScanGrid& grid,
                                          const LoamFeatures& features, const std::vector<std::uint32_t>* positions,
                                          LoamPointFormat format, sensor_msgs::PointCloud2Ptr reuse = {},
                                          const SweepDeskew* deskew = nullptr);

}  // namespace ring_curvature
