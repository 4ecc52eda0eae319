# The scene simulator (Python, tools/simulate_scene with its module folder tools/rc_eval; numpy
# only): synthetic sweeps with per-point ground truth. In the source tree rosrun finds it in
# tools/; installed, it goes to the package's bin folder with its module folder beside it.
# install(PROGRAMS), not catkin_install_python: the latter also writes devel-space wrappers, and
# rosrun would then find the tool twice and stop to ask which one to run.
# The other evaluation tools (tools/evaluate, tools/accuracy_sweep) score the core against the
# PCL baselines: they run from the source tree on a build with the lab (cmake/lab.cmake) and
# are not installed.
install(PROGRAMS tools/simulate_scene DESTINATION ${CATKIN_PACKAGE_BIN_DESTINATION})
install(DIRECTORY tools/rc_eval DESTINATION ${CATKIN_PACKAGE_BIN_DESTINATION}
  PATTERN "__pycache__" EXCLUDE)
