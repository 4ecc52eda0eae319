// What the in-process nodelet tests (test_nodelet_inprocess.cpp, test_nodelet_inprocess_loam.cpp)
// share: bounded waits, the fixture's frames, a nodelet manager in the test process and the
// tests' main.
#pragma once

#include <gtest/gtest.h>
#include <nodelet/loader.h>
#include <ros/ros.h>
#include <sensor_msgs/PointCloud2.h>

#include <boost/make_shared.hpp>
#include <functional>
#include <string>
#include <vector>

#include "ring_curvature/ros/ring_curvature_nodelet.hpp"
#include "cloud_builders.hpp"

namespace ring_curvature_test
{

inline constexpr double kTimeout = 10.0;  // [s] bound on every wait

inline bool waitUntil(const std::function<bool()>& cond, double seconds = kTimeout)
{
  const ros::WallTime end = ros::WallTime::now() + ros::WallDuration(seconds);
  while (!cond())
  {
    if (ros::WallTime::now() > end || !ros::ok())
      return false;
    ros::WallDuration(0.005).sleep();
  }
  return true;
}

inline const std::vector<sensor_msgs::PointCloud2::ConstPtr>& frames()
{
  static const auto f =
      readClouds(std::string(RC_SOURCE_DIR) + "/rosbag_fixtures/nebula_vlp16_lastreturn_4scans.bag", "/velodyne_points");
  return f;
}

// A manager whose instances the test can reach (the factory keeps a pointer to each).
class Manager
{
public:
  Manager()
    : loader_([this](const std::string&) {
        auto n = boost::make_shared<ring_curvature::RingCurvatureNodelet>();
        last_ = n;
        return n;
      })
  {
  }
  boost::shared_ptr<ring_curvature::RingCurvatureNodelet> load(const std::string& name, const std::string& input)
  {
    nodelet::M_string remap{{ros::names::resolve("velodyne_points"), ros::names::resolve(input)}};
    if (!loader_.load(name, "ring_curvature/RingCurvatureNodelet", remap, {}))
      return nullptr;
    return last_;
  }
  bool unload(const std::string& name) { return loader_.unload(name); }

private:
  // Declared before last_ so that the nodelets die inside the loader's destructor, while the
  // callback queues their timers and subscribers use still exist (as in a real manager).
  nodelet::Loader loader_;
  boost::shared_ptr<ring_curvature::RingCurvatureNodelet> last_;
};

inline sensor_msgs::PointCloud2::Ptr copyOf(const sensor_msgs::PointCloud2& c)
{
  return boost::make_shared<sensor_msgs::PointCloud2>(c);
}

/// The tests' main: gtest and ROS initialized, the callbacks (the nodelets' and the tests'
/// subscribers') on a spinner of two threads while the tests run.
inline int runTests(int argc, char** argv, const std::string& node_name)
{
  testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, node_name);
  ros::AsyncSpinner spinner(2);
  spinner.start();
  const int r = RUN_ALL_TESTS();
  spinner.stop();
  ros::shutdown();
  return r;
}

}  // namespace ring_curvature_test
