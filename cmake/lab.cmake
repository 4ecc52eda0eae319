# The lab, built only with RC_BUILD_LAB=ON (scripts/test and the benchmark scripts set it) and
# never installed: the paper's PCL baselines (PCA curvature, Euclidean clustering), the
# benchmarks, the in-process A/B harness, the evaluation's C++ helpers, and the tests that need
# PCL. The product (core, ROS layer, nodelet, node, process_bag) needs none of it.
#
# PCL's VTK-linked components need MPI::MPI_C at generate time; asking for MPI first (and for
# only the PCL components used here, none of which is VTK-based) keeps configuration working.
find_package(MPI COMPONENTS C)
# The lab's targets are never installed (they are not part of the package users get).
#catkin_lint: ignore uninstalled_target
find_package(PCL REQUIRED COMPONENTS common search kdtree features segmentation)
find_package(pcl_conversions REQUIRED)

add_library(ring_curvature_baselines
  src/baselines/xyz_cloud.cpp
  src/baselines/pca_curvature.cpp
  src/baselines/euclidean_clustering.cpp)
# the baselines' headers (src/baselines/*.hpp, included as "baselines/...") are the lab's alone
target_include_directories(ring_curvature_baselines PUBLIC include src)
# SYSTEM: PCL's headers are not warning-clean under -Wpedantic (anonymous structs).
#catkin_lint: ignore_once external_interface_path
target_include_directories(ring_curvature_baselines SYSTEM PUBLIC ${PCL_INCLUDE_DIRS})
target_compile_definitions(ring_curvature_baselines PUBLIC ${PCL_DEFINITIONS})
target_link_libraries(ring_curvature_baselines PUBLIC ring_curvature_core ${PCL_LIBRARIES})
target_compile_options(ring_curvature_baselines PRIVATE ${RC_WARNINGS})

# Clouds are read with the ROS layer's adapter (ring_curvature_ros: makeView), exactly as the
# nodelet reads them.
add_executable(benchmark src/tools/benchmark.cpp)
target_link_libraries(benchmark ring_curvature_baselines ring_curvature_ros ${catkin_LIBRARIES})
target_compile_options(benchmark PRIVATE ${RC_WARNINGS})

add_executable(baseline_labels src/tools/baseline_labels.cpp src/tools/bench_label_cloud.cpp)
target_link_libraries(baseline_labels ring_curvature_baselines ring_curvature_ros ${catkin_LIBRARIES})
target_compile_options(baseline_labels PRIVATE ${RC_WARNINGS})

# The nodelet in a real manager, timed from outside (src/tools/benchmark_nodelet.sh runs it
# with a private ROS master). Loads the plugin by name: it does not link the ROS library.
add_executable(benchmark_nodelet src/tools/benchmark_nodelet.cpp)
target_include_directories(benchmark_nodelet PRIVATE include)
target_include_directories(benchmark_nodelet SYSTEM PRIVATE ${catkin_INCLUDE_DIRS})
target_link_libraries(benchmark_nodelet ${catkin_LIBRARIES})
add_dependencies(benchmark_nodelet ${PROJECT_NAME}_generate_messages_cpp)
target_compile_options(benchmark_nodelet PRIVATE ${RC_WARNINGS})

# In-process A/B timing of two builds of the core (src/tools/ab_core.sh). ab_core does not link
# the core: it loads two builds of it, each with its own copy of the shim, into two link
# namespaces. Every build carries the shim compiled against its own headers; ab_core.sh
# compiles one for a build that lacks it.
add_library(ring_curvature_ab_shim SHARED src/tools/ab_shim.cpp)
target_link_libraries(ring_curvature_ab_shim ring_curvature_core)
target_compile_options(ring_curvature_ab_shim PRIVATE ${RC_WARNINGS})
add_executable(ab_core src/tools/ab_core.cpp src/tools/ab_build.cpp src/tools/ab_frames.cpp)
target_include_directories(ab_core SYSTEM PRIVATE ${catkin_INCLUDE_DIRS} ${EIGEN3_INCLUDE_DIRS})
# the project's headers for the default field lists only: ab_core still links no build of the core
target_include_directories(ab_core PRIVATE include)
target_link_libraries(ab_core ${catkin_LIBRARIES} ${CMAKE_DL_LIBS})
target_compile_options(ab_core PRIVATE ${RC_WARNINGS})

# Figure 4 (convergence): the Table-1 CSV from the same analytic traces as
# test/core/test_convergence.cpp, so the plotted figure is what that test asserts
# (tools/evaluate and test/evaluation run it).
add_executable(convergence_table tools/convergence_table.cpp)
target_include_directories(convergence_table PRIVATE ${CMAKE_CURRENT_SOURCE_DIR}/test)
target_link_libraries(convergence_table ring_curvature_core)
target_compile_options(convergence_table PRIVATE ${RC_WARNINGS})

if(CATKIN_ENABLE_TESTING)
  # The baselines label what they should on a scene whose answer is known.
  catkin_add_gtest(test_baselines test/alloc/test_baselines.cpp test/alloc/synthetic_scene.cpp)
  if(TARGET test_baselines)
    target_link_libraries(test_baselines ring_curvature_baselines)
    target_compile_options(test_baselines PRIVATE ${RC_WARNINGS})
  endif()
  # The public PCL point type (include/ring_curvature/point_types.hpp, header-only: its users
  # bring PCL) read with pcl::fromROSMsg from the nodelet's output.
  catkin_add_gtest(test_ros_point_types test/ros/test_point_types.cpp)
  if(TARGET test_ros_point_types)
    target_link_libraries(test_ros_point_types ring_curvature_ros ${PCL_LIBRARIES} gtest_main)
    target_include_directories(test_ros_point_types SYSTEM PRIVATE ${PCL_INCLUDE_DIRS} ${pcl_conversions_INCLUDE_DIRS})
    target_compile_definitions(test_ros_point_types PRIVATE RC_SOURCE_DIR="${CMAKE_CURRENT_SOURCE_DIR}")
    target_compile_options(test_ros_point_types PRIVATE ${RC_WARNINGS})
  endif()
endif()
