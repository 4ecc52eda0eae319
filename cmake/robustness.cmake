# Robustness: no allocation per frame, malformed and degenerate input through the core (gtest).
# The sanitizer build (test/sanitize/, run by scripts/test.d/40-sanitizers) and the fuzz target
# (test/fuzz/, run by scripts/test.d/50-fuzz) are separate clang projects, because catkin's gcc
# build cannot carry -fsanitize=fuzzer and instrumenting the whole catkin build would slow every
# other test.
if(CATKIN_ENABLE_TESTING)
  # No heap allocation per frame once warm (issue 6). The test binary interposes malloc, so it
  # must not share a process with anything else: its own executable. The core alone, no PCL.
  catkin_add_gtest(test_alloc test/alloc/test_pipeline_alloc.cpp test/alloc/alloc_counter.cpp
    test/alloc/synthetic_scene.cpp)
  if(TARGET test_alloc)
    target_link_libraries(test_alloc ring_curvature_core)
    target_compile_options(test_alloc PRIVATE ${RC_WARNINGS})
  endif()
  # Malformed clouds (rejected) and degenerate ones (legal) through the core.
  foreach(t malformed_cloud degenerate_cloud)
    catkin_add_gtest(robustness_${t} test/robustness/${t}_test.cpp)
    if(TARGET robustness_${t})
      # catkin_add_gtest links gtest without its main()
      target_link_libraries(robustness_${t} ring_curvature_core GTest::gtest_main)
      target_compile_options(robustness_${t} PRIVATE ${RC_WARNINGS})
    endif()
  endforeach()
  # The same malformed clouds as sensor_msgs/PointCloud2 through the adapter and FrameProcessor.
  catkin_add_gtest(robustness_malformed_msg test/robustness/malformed_msg_test.cpp)
  if(TARGET robustness_malformed_msg)
    target_link_libraries(robustness_malformed_msg ring_curvature_ros GTest::gtest_main)
    target_compile_options(robustness_malformed_msg PRIVATE ${RC_WARNINGS})
  endif()
  # ... and through the running nodelet, with diagnostics checked (Python checker; rostest is
  # found by cmake/ros_tests.cmake).
  add_rostest(test/robustness/malformed_nodelet.test DEPENDENCIES ring_curvature_ros)
endif()
