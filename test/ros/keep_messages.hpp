// A test's subscription that keeps every message it receives, for the test thread to read
// under the same mutex.
#pragma once

#include <ros/ros.h>

#include <mutex>
#include <string>
#include <vector>

namespace ring_curvature_test
{

template <class M>
ros::Subscriber keepMessages(ros::NodeHandle& nh, const std::string& topic, std::mutex& mutex,
                             std::vector<typename M::ConstPtr>& into)
{
  return nh.subscribe<M>(topic, 10, [&mutex, &into](const typename M::ConstPtr& m) {
    std::lock_guard<std::mutex> l(mutex);
    into.push_back(m);
  });
}

}  // namespace ring_curvature_test
