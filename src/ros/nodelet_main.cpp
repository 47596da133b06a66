// A standalone node that runs one nodelet in its own process, for users who
// do not want a manager. Built once per nodelet with RISAS_NODELET naming the
// class, as image_pipeline's nodes are.
#include <nodelet/loader.h>
#include <ros/ros.h>

int main(int argc, char** argv) {
  ros::init(argc, argv, RISAS_NODE_NAME);
  nodelet::Loader loader;
  const nodelet::M_string remappings(ros::names::getRemappings());
  const nodelet::V_string arguments(argv + 1, argv + argc);
  if (!loader.load(ros::this_node::getName(), RISAS_NODELET, remappings, arguments)) {
    ROS_FATAL("could not load nodelet %s", RISAS_NODELET);
    return 1;
  }
  ros::spin();
  return 0;
}
