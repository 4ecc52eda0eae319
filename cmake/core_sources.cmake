# The core library's sources, one list for every build of it: the catkin build (cmake/core.cmake)
# and the portable cross build of the core and its unit tests (test/cross/).
set(RC_CORE_SOURCES
  src/core/grid/cloud_view_checks.cpp
  src/core/grid/input_pass.cpp
  src/core/grid/organized_placement.cpp
  src/core/grid/organized_avx2.cpp
  src/core/grid/ring_sort.cpp
  src/core/grid/ring_order.cpp
  src/core/grid/resolution.cpp
  src/core/grid/vertical_neighbours.cpp
  src/core/grid/scan_grid_builder.cpp
  src/core/features/feature_computer.cpp
  src/core/features/ring_kernels.cpp
  src/core/features/smoothness.cpp
  src/core/features/smoothness_direct.cpp
  src/core/classification/rank_select.cpp
  src/core/classification/binned_selection.cpp
  src/core/classification/bin_candidates.cpp
  src/core/classification/ring_thresholds.cpp
  src/core/classification/classifier.cpp
  src/core/classification/inter_ring.cpp
  src/core/classification/inter_ring_windows.cpp
  src/core/primitives/ring_unions.cpp
  src/core/primitives/primitive_sums.cpp
  src/core/primitives/covariance_axis.cpp
  src/core/primitives/primitive_extractor.cpp
  src/core/loam/loam_selector.cpp
  src/core/loam/degeneracy.cpp
  src/core/loam/sweep_deskew.cpp
  src/core/pipeline/types.cpp
  src/core/pipeline/params.cpp
  src/core/pipeline/output_gather.cpp
  src/core/pipeline/pipeline.cpp
)
# Floating-point options every build of the core takes:
# -fno-math-errno: the core never reads errno; without it every std::sqrt keeps a branch to libm,
#   which stops loops with square roots from vectorizing (sqrt is correctly rounded either way).
# -fno-trapping-math: nor does it read FP exception flags; lets `c ? a / b : nan` if-convert.
# -ffp-contract=off: no fused multiply-adds formed behind the code's back. They round once where
#   two operations round twice, so an FMA target (AArch64 contracts by default) would give
#   other bits than x86-64's baseline; with this every architecture computes the same labels.
set(RC_CORE_OPTIONS -fno-math-errno -fno-trapping-math -ffp-contract=off)
# The stages' private headers, included as "stage/file.hpp" (and the shared ones by name).
set(RC_CORE_PRIVATE_INCLUDE src/core)
