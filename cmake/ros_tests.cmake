# Tests of the ROS layer: gtest without a master (adapter, outputs, parameters), rostests with
# a master (the nodelet in-process; bag replays through node and nodelet), launch file checks.
if(CATKIN_ENABLE_TESTING)
  find_package(rostest REQUIRED)
  find_package(roslaunch REQUIRED)

  # gtest binaries on the ROS library without a master, one per file test/ros/test_<name>.cpp:
  # the adapter and the outputs; parameters (the YAML file, parsing by key, dynamic_reconfigure's
  # Config and back); real drivers' point layouts and the field-name parameters, and the layouts
  # it rejects; deskewing the LOAM clouds (the odometry's motion model, FrameProcessor's points).
  foreach(t cloud_adapter param_loading driver_layouts driver_layout_errors deskew)
    catkin_add_gtest(test_ros_${t} test/ros/test_${t}.cpp)
    if(TARGET test_ros_${t})
      target_link_libraries(test_ros_${t} ring_curvature_ros gtest_main)
      target_compile_definitions(test_ros_${t} PRIVATE RC_SOURCE_DIR="${CMAKE_CURRENT_SOURCE_DIR}")
      target_compile_options(test_ros_${t} PRIVATE ${RC_WARNINGS})
    endif()
  endforeach()

  # (The PCL point type's test, test_ros_point_types, is in cmake/lab.cmake: it needs PCL.)

  # The nodelet in the test process: its outputs (test_nodelet_inprocess.cpp), and its LOAM
  # outputs and their deskewing (test_nodelet_inprocess_loam.cpp); each its own .test.
  foreach(t nodelet_inprocess nodelet_inprocess_loam)
    add_rostest_gtest(test_ros_${t} test/ros/${t}.test test/ros/test_${t}.cpp)
    target_link_libraries(test_ros_${t} ring_curvature_ros)
    target_compile_definitions(test_ros_${t} PRIVATE RC_SOURCE_DIR="${CMAKE_CURRENT_SOURCE_DIR}")
    target_compile_options(test_ros_${t} PRIVATE ${RC_WARNINGS})
  endforeach()

  # One checker binary, several replays (add_rostest_gtest would build it once per .test).
  add_executable(test_ros_replay_checker test/ros/test_replay_checker.cpp)
  target_link_libraries(test_ros_replay_checker ring_curvature_ros ${GTEST_LIBRARIES})
  target_include_directories(test_ros_replay_checker SYSTEM PRIVATE ${GTEST_INCLUDE_DIRS})
  target_compile_options(test_ros_replay_checker PRIVATE ${RC_WARNINGS})
  add_dependencies(tests test_ros_replay_checker)
  foreach(t node_replay nodelet_replay ouster_replay)
    add_rostest(test/ros/${t}.test DEPENDENCIES test_ros_replay_checker ring_curvature_node ring_curvature_ros)
  endforeach()

  # The velodyne driver is not in Debian: without it, check vlp16.launch with driver:=false.
  find_package(velodyne_pointcloud QUIET)
  roslaunch_add_file_check(launch/ring_curvature.launch)
  roslaunch_add_file_check(launch/replay.launch)
  if(velodyne_pointcloud_FOUND)
    roslaunch_add_file_check(launch/vlp16.launch)
  else()
    roslaunch_add_file_check(launch/vlp16.launch driver:=false)
  endif()
  roslaunch_add_file_check(test/ros)
endif()
