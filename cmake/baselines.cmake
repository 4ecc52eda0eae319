# PCL baselines of the paper (PCA curvature, Euclidean clustering), the benchmark, and the
# allocation-counting test of the core.
#
# PCL's VTK-linked components need MPI::MPI_C at generate time; asking for MPI first (and for
# only the PCL components used here, none of which is VTK-based) keeps configuration working.
find_package(MPI COMPONENTS C)
find_package(PCL REQUIRED COMPONENTS common search kdtree features segmentation)

add_library(ring_curvature_baselines
  src/baselines/xyz_cloud.cpp
  src/baselines/pca_curvature.cpp
  src/baselines/euclidean_clustering.cpp)
target_include_directories(ring_curvature_baselines PUBLIC include)
# SYSTEM: PCL's headers are not warning-clean under -Wpedantic (anonymous structs).
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

install(TARGETS ring_curvature_baselines
  ARCHIVE DESTINATION ${CATKIN_PACKAGE_LIB_DESTINATION}
  LIBRARY DESTINATION ${CATKIN_PACKAGE_LIB_DESTINATION})
install(TARGETS benchmark baseline_labels RUNTIME DESTINATION ${CATKIN_PACKAGE_BIN_DESTINATION})

if(CATKIN_ENABLE_TESTING)
  # No heap allocation per frame once warm (issue 6). The test binary interposes malloc, so it
  # must not share a process with anything else: its own executable.
  catkin_add_gtest(test_alloc test/alloc/test_pipeline_alloc.cpp test/alloc/alloc_counter.cpp
    test/alloc/synthetic_scene.cpp)
  if(TARGET test_alloc)
    target_link_libraries(test_alloc ring_curvature_core)
    target_compile_options(test_alloc PRIVATE ${RC_WARNINGS})
  endif()
  # The baselines label what they should on a scene whose answer is known.
  catkin_add_gtest(test_baselines test/alloc/test_baselines.cpp test/alloc/synthetic_scene.cpp)
  if(TARGET test_baselines)
    target_link_libraries(test_baselines ring_curvature_baselines)
    target_compile_options(test_baselines PRIVATE ${RC_WARNINGS})
  endif()
endif()

# The nodelet in a real manager, timed from outside (src/tools/benchmark_nodelet.sh runs it
# with a private ROS master). Loads the plugin by name: it does not link the ROS library.
add_executable(benchmark_nodelet src/tools/benchmark_nodelet.cpp)
target_include_directories(benchmark_nodelet PRIVATE include ${CATKIN_DEVEL_PREFIX}/${CATKIN_GLOBAL_INCLUDE_DESTINATION})
target_include_directories(benchmark_nodelet SYSTEM PRIVATE ${catkin_INCLUDE_DIRS})
target_link_libraries(benchmark_nodelet ${catkin_LIBRARIES})
add_dependencies(benchmark_nodelet ${PROJECT_NAME}_generate_messages_cpp)
target_compile_options(benchmark_nodelet PRIVATE ${RC_WARNINGS})
install(TARGETS benchmark_nodelet RUNTIME DESTINATION ${CATKIN_PACKAGE_BIN_DESTINATION})

# In-process A/B timing of two builds of the core (src/tools/ab_core.sh). ab_core does not link
# the core: it loads two builds of it, each with its own copy of the shim, into two link
# namespaces. Every build carries the shim compiled against its own headers; ab_core.sh
# compiles one for a build that lacks it.
add_library(ring_curvature_ab_shim SHARED src/tools/ab_shim.cpp)
target_link_libraries(ring_curvature_ab_shim ring_curvature_core)
target_compile_options(ring_curvature_ab_shim PRIVATE ${RC_WARNINGS})
add_executable(ab_core src/tools/ab_core.cpp)
target_include_directories(ab_core SYSTEM PRIVATE ${catkin_INCLUDE_DIRS} ${EIGEN3_INCLUDE_DIRS})
# the project's headers for the adapter's constants only: ab_core still links no build of the core
target_include_directories(ab_core PRIVATE include)
target_link_libraries(ab_core ${catkin_LIBRARIES} ${CMAKE_DL_LIBS})
target_compile_options(ab_core PRIVATE ${RC_WARNINGS})
install(TARGETS ring_curvature_ab_shim
  ARCHIVE DESTINATION ${CATKIN_PACKAGE_LIB_DESTINATION}
  LIBRARY DESTINATION ${CATKIN_PACKAGE_LIB_DESTINATION})
install(TARGETS ab_core RUNTIME DESTINATION ${CATKIN_PACKAGE_BIN_DESTINATION})
