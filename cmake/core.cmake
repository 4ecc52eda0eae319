# The ROS-free core: Eigen only, no roscpp, no PCL.
include(${CMAKE_CURRENT_LIST_DIR}/core_sources.cmake)
add_library(ring_curvature_core ${RC_CORE_SOURCES})
target_include_directories(ring_curvature_core PUBLIC include)
# SYSTEM: GCC 12 warns (maybe-uninitialized) inside Eigen's own eigensolver. PUBLIC: the public
# headers use Eigen's types.
#catkin_lint: ignore_once external_interface_path
target_include_directories(ring_curvature_core SYSTEM PUBLIC ${EIGEN3_INCLUDE_DIRS})
target_include_directories(ring_curvature_core PRIVATE ${RC_CORE_PRIVATE_INCLUDE})
target_compile_options(ring_curvature_core PRIVATE ${RC_WARNINGS})
target_compile_options(ring_curvature_core PRIVATE ${RC_CORE_OPTIONS})
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
