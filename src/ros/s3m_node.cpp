// s3m_node: semantic RGB-D SLAM as a ROS1 node (see node.hpp and README.md, "ROS1").
#include <ros/ros.h>

#include "node.hpp"

int main(int argc, char** argv) {
  ros::init(argc, argv, "s3m_node");
  ros::NodeHandle nh, pnh("~");
  try {
    s3m::ros1::S3mNode node(nh, pnh);
    ros::spin();      // until SIGINT / rosnode kill / a fatal frame error
    node.shutdown();  // finish the pipeline and save (~save_on_exit) before ROS goes away
    if (node.failed()) return 1;
  } catch (const std::exception& e) {
    ROS_FATAL("s3m_node: %s", e.what());
    return 1;
  }
  return 0;
}
