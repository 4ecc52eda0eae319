# Evaluation tools (Python, in tools/): the scene simulator with ground truth, the accuracy
# sweep over modes, and the report of the paper's metrics. In the source tree rosrun finds them
# in tools/; installed, they go to the package's bin folder with their module folder beside
# them. install(PROGRAMS), not catkin_install_python: the latter also writes devel-space
# wrappers, and rosrun would then find each tool twice and stop to ask which one to run.
install(PROGRAMS tools/simulate_scene tools/accuracy_sweep tools/evaluate
  DESTINATION ${CATKIN_PACKAGE_BIN_DESTINATION})
install(DIRECTORY tools/rc_eval DESTINATION ${CATKIN_PACKAGE_BIN_DESTINATION}
  PATTERN "__pycache__" EXCLUDE)
install(DIRECTORY rosbag_fixtures/ DESTINATION ${CATKIN_PACKAGE_SHARE_DESTINATION}/rosbag_fixtures
  FILES_MATCHING PATTERN "synthetic_*")

# Figure 4 (convergence): the Table-1 CSV from the same analytic traces as
# test/core/test_convergence.cpp, so the plotted figure is what that test asserts.
add_executable(convergence_table tools/convergence_table.cpp)
target_include_directories(convergence_table PRIVATE ${CMAKE_CURRENT_SOURCE_DIR}/test)
target_link_libraries(convergence_table ring_curvature_core)
target_compile_options(convergence_table PRIVATE ${RC_WARNINGS})
install(TARGETS convergence_table RUNTIME DESTINATION ${CATKIN_PACKAGE_BIN_DESTINATION})
