# rviz side: the markers gtest. makePrimitiveMarkers lives in ring_curvature_ros (cmake/ros.cmake
# adds src/ros/markers.cpp to it), so the test exists only when that library does.
# The rviz screenshot test is scripts/test.d/30-rviz-screenshot (it needs Xvfb and a whole
# bag replay, which is not a unit test).
if(CATKIN_ENABLE_TESTING AND TARGET ring_curvature_ros)
  catkin_add_gtest(test_markers test/viz/markers_test.cpp)
  if(TARGET test_markers)
    target_link_libraries(test_markers ring_curvature_ros ${catkin_LIBRARIES})
    target_include_directories(test_markers PRIVATE include ${catkin_INCLUDE_DIRS})
    target_compile_options(test_markers PRIVATE ${RC_WARNINGS})
  endif()
endif()
