// Section 4.3: connected components of same-label neighbours on the scan grid (union-find,
// linear time) and a geometric summary of each component.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <vector>

#include "ring_curvature/features.hpp"
#include "ring_curvature/uninitialized_vector.hpp"

namespace ring_curvature
{

/// One primitive. (Named PrimitiveInfo because the message msg/Primitive.msg generates
/// ring_curvature::Primitive, and a user may include both.)
struct PrimitiveInfo
{
  std::uint32_t id = 0;           ///< index in PrimitiveSet::primitives
  Label label = Label::None;
  std::uint32_t num_points = 0;
  std::uint32_t first = 0;        ///< offset of its indices in PrimitiveSet::indices
  Eigen::Vector3f centroid = Eigen::Vector3f::Zero();
  Eigen::Vector3f axis = Eigen::Vector3f::Zero();         ///< PLANE: unit normal; else principal direction
  Eigen::Vector3f eigenvalues = Eigen::Vector3f::Zero();  ///< covariance eigenvalues, ascending [m^2]
  /// covariance of the points (duplicates included) about their mean, divided by num_points
  /// [m^2]: what `eigenvalues` and `axis` come from, e.g. for a SLAM factor's weight or a
  /// patch's in-plane extent
  Eigen::Matrix3f covariance = Eigen::Matrix3f::Zero();
  Eigen::Vector3f bbox_min = Eigen::Vector3f::Zero(), bbox_max = Eigen::Vector3f::Zero();
  float rms_error = 0;            ///< PLANE: RMS distance to the plane; EDGE: to the line [m]
  std::uint16_t ring_min = 0, ring_max = 0;
};

struct PrimitiveSet
{
  std::vector<PrimitiveInfo> primitives;
  std::vector<std::uint32_t> indices;       ///< input point indices, grouped per primitive
  std::vector<std::int32_t> of_grid;        ///< primitive id of each grid position, -1 if none
  void clear() { primitives.clear(); indices.clear(); of_grid.clear(); }
};

class PrimitiveExtractor
{
public:
  void extract(const ScanGrid& grid, const std::vector<Label>& labels, const Params& params,
               PrimitiveSet& out);

  /// A maximal stretch [begin, end) of one ring whose neighbours all unite (Eq 19-20, same
  /// wanted label): one component without any union-find work per point.
  struct Run
  {
    std::uint32_t begin, end;
    std::uint32_t rank;  ///< points of its component before it (grid order)
  };

private:
  // Scratch, every entry written before it is read: a resize need not zero-fill what exceeds
  // the last frame's size (std::vector's did, for several arrays a frame as sizes vary).
  UninitializedVector<std::uint32_t> parent_;   // union-find forest over the run ids
  UninitializedVector<std::uint32_t> run_;      // run id of each grid position (unwanted label: none)
  UninitializedVector<std::uint8_t> join_;      // 1 where a position joins its predecessor's run
  UninitializedVector<Run> runs_;               // the runs of wanted labels, in grid order: by id
  UninitializedVector<std::int32_t> comp_;      // at each root: component size, then primitive id or -1
  UninitializedVector<std::uint32_t> roots_;    // the roots (run ids), in grid order
  UninitializedVector<std::uint32_t> grid_size_; // grid points per root, then per primitive id
  UninitializedVector<std::uint32_t> dup_root_; // root of each duplicate's component (none if unwanted)
  UninitializedVector<std::uint32_t> dup_rank_; // points of that component before the duplicate
  UninitializedVector<std::uint32_t> run_begins_, run_ends_;  // a ring's runs as cutRingAvx2 lists them
  UninitializedVector<std::uint64_t> vertical_pairs_;  // a ring's run pairs as verticalPairsAvx512 lists them
  UninitializedVector<std::uint32_t> slot_pos_;  // grid position of each grid point's entry of PrimitiveSet::indices
  // Scratch kept zero between frames (a plain vector: a resize zero-fills new entries).
  std::vector<std::uint32_t> dup_count_;  // per grid position: the duplicates it represents
  bool dup_count_zero_ = true;            // false while dup_count_ holds counts
};

}  // namespace ring_curvature
