# The ROS layer: cloud adapter, parameter loading, output messages, FrameProcessor, the nodelet
# (all in ring_curvature_ros, listed in nodelet_plugins.xml), the node that loads it, and the
# offline process_bag tool. Both executables only link the library: nothing is compiled twice.
set(RC_ROS_SOURCES
  src/ros/cloud_adapter.cpp
  src/ros/outputs.cpp
  src/ros/label_subsets.cpp
  src/ros/loam_outputs.cpp
  src/ros/odometry_motion.cpp
  src/ros/lidar_mounting.cpp
  src/ros/primitive_message.cpp
  src/ros/param_table.cpp
  src/ros/param_server.cpp
  src/ros/param_file.cpp
  src/ros/param_reconfigure.cpp
  src/ros/frame_processor.cpp
  src/ros/ring_curvature_nodelet.cpp)
# Written by another part of the package (rviz markers); required by FrameProcessor.
if(EXISTS ${CMAKE_CURRENT_SOURCE_DIR}/src/ros/markers.cpp)
  list(APPEND RC_ROS_SOURCES src/ros/markers.cpp src/ros/primitive_points.cpp)
endif()

add_library(ring_curvature_ros ${RC_ROS_SOURCES})
# (the generated message and config headers: generate_messages() puts the devel space's include
# directory on every target's path)
target_include_directories(ring_curvature_ros PUBLIC include)
# The public headers include ROS's: users of the library need them too.
#catkin_lint: ignore_once external_interface_path
target_include_directories(ring_curvature_ros SYSTEM PUBLIC ${catkin_INCLUDE_DIRS})
target_link_libraries(ring_curvature_ros ring_curvature_core ${catkin_LIBRARIES})
add_dependencies(ring_curvature_ros ${PROJECT_NAME}_generate_messages_cpp ${PROJECT_NAME}_gencfg)
target_compile_options(ring_curvature_ros PRIVATE ${RC_WARNINGS})

add_executable(ring_curvature_node src/nodes/ring_curvature_node.cpp)
target_link_libraries(ring_curvature_node ring_curvature_ros)
target_compile_options(ring_curvature_node PRIVATE ${RC_WARNINGS})

# In the package's lib dir (catkin's default for add_executable) so `rosrun ring_curvature process_bag` finds it.
add_executable(process_bag src/nodes/process_bag.cpp)
target_link_libraries(process_bag ring_curvature_ros)
target_compile_options(process_bag PRIVATE ${RC_WARNINGS})

install(TARGETS ring_curvature_ros
  ARCHIVE DESTINATION ${CATKIN_PACKAGE_LIB_DESTINATION}
  LIBRARY DESTINATION ${CATKIN_PACKAGE_LIB_DESTINATION})
install(TARGETS ring_curvature_node process_bag
  RUNTIME DESTINATION ${CATKIN_PACKAGE_BIN_DESTINATION})
install(FILES nodelet_plugins.xml DESTINATION ${CATKIN_PACKAGE_SHARE_DESTINATION})
install(DIRECTORY launch config DESTINATION ${CATKIN_PACKAGE_SHARE_DESTINATION})
