// Standalone node: loads RingCurvatureNodelet in-process through nodelet::Loader, so the node
// and the nodelet are one compiled code path (as image_proc does).
#include <nodelet/loader.h>
#include <ros/ros.h>

int main(int argc, char** argv)
{
  ros::init(argc, argv, "ring_curvature");
  // No manager services: this process hosts exactly one nodelet.
  nodelet::Loader loader(false);
  const nodelet::M_string remappings = ros::names::getRemappings();
  nodelet::V_string my_argv(argv + 1, argv + argc);
  if (!loader.load(ros::this_node::getName(), "ring_curvature/RingCurvatureNodelet", remappings, my_argv))
  {
    ROS_FATAL("could not load ring_curvature/RingCurvatureNodelet (see the messages above)");
    return 1;
  }
  ros::spin();
  return 0;
}
