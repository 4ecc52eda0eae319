# The ROS-free core: Eigen only, no roscpp, no PCL.
add_library(ring_curvature_core
  src/core/types.cpp
  src/core/params.cpp
  src/core/scan_grid.cpp
  src/core/grid_input.cpp
  src/core/ring_sort.cpp
  src/core/ring_fold.cpp
  src/core/grid_organized.cpp
  src/core/grid_resolution.cpp
  src/core/grid_vertical.cpp
  src/core/cloud_view_checks.cpp
  src/core/features.cpp
  src/core/smoothness.cpp
  src/core/classifier.cpp
  src/core/thresholds.cpp
  src/core/primitives.cpp
  src/core/primitive_sums.cpp
  src/core/covariance_axis.cpp
  src/core/primitive_runs.cpp
  src/core/vertical_pairs.cpp
  src/core/pipeline.cpp
  src/core/cpu_tuning.cpp)
target_include_directories(ring_curvature_core PUBLIC include ${EIGEN3_INCLUDE_DIRS})
target_compile_options(ring_curvature_core PRIVATE ${RC_WARNINGS})
# The core never reads errno. Without this, every std::sqrt keeps a branch to libm (to set errno
# on negative input), which stops the compiler from vectorizing the loops that take square roots.
# Results are unchanged: sqrt is correctly rounded either way. (No -ffast-math: that would.)
target_compile_options(ring_curvature_core PRIVATE -fno-math-errno)
# Nor does it read floating-point exception flags: this lets the compiler form both sides of a
# selection (if-conversion), which vectorizes loops with `c ? a / b : nan`. Values are unchanged.
target_compile_options(ring_curvature_core PRIVATE -fno-trapping-math)
# No fused multiply-adds formed from a multiply and an add: they round once where the two
# operations round twice, so a clone for a CPU with FMA (the AVX-512 feature kernels, see
# src/core/simd_clones.hpp) would give other bits than the baseline. Without FMA in the target
# (the baseline and AVX2 code) this changes nothing.
target_compile_options(ring_curvature_core PRIVATE -ffp-contract=off)
# Hot loops are compiled for baseline x86-64 and for AVX2 (src/core/simd_clones.hpp); OFF builds
# the baseline alone (to check that both give the same bits, or for a toolchain without ifunc).
option(RC_SIMD_CLONES "AVX2 versions of the core's hot loops, chosen at load time" ON)
if(NOT RC_SIMD_CLONES)
  target_compile_definitions(ring_curvature_core PRIVATE RC_NO_SIMD_CLONES)
endif()
install(TARGETS ring_curvature_core
  ARCHIVE DESTINATION ${CATKIN_PACKAGE_LIB_DESTINATION}
  LIBRARY DESTINATION ${CATKIN_PACKAGE_LIB_DESTINATION})
install(DIRECTORY include/${PROJECT_NAME}/ DESTINATION ${CATKIN_PACKAGE_INCLUDE_DESTINATION})
