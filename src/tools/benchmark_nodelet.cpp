// rosrun ring_curvature benchmark_nodelet --bag IN.bag [--repeat N] [--topic T]
// (needs a ROS master: src/tools/benchmark_nodelet.sh starts a private one)
//
// The nodelet in a real nodelet manager (nodelet::Loader, in this process), fed every
// PointCloud2 of a bag by shared pointer, with a subscriber on each of its five outputs so it
// builds them all. One frame at a time: the time from publishing the input to the arrival of the
// LAST output is "callback entry to last publish" plus two intra-process hand-offs (queue ->
// manager thread, publish -> this process's spinner), so it bounds the callback from above. The
// nodelet's own ~frame_stats gives the callback's time itself (entry to last publish, steady
// clock) and its split into the core and the message building, and the core's stages (to set
// beside `benchmark`'s, run on the same bag); those are reported too.
// The LAST line is key=value pairs: frames=… points=… nodelet_ms=… nodelet_p90_ms=… callback_ms=…
// callback_p90_ms=… core_ms=… messages_ms=…
#include <nodelet/loader.h>
#include <ros/ros.h>
#include <rosbag/bag.h>
#include <rosbag/query.h>
#include <rosbag/view.h>
#include <sensor_msgs/PointCloud2.h>
#include <visualization_msgs/MarkerArray.h>

#include "ring_curvature/FrameStats.h"
#include "ring_curvature/PrimitiveArray.h"

#include <chrono>
#include <condition_variable>
#include <cstdio>
#include <cstdlib>
#include <iostream>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "bench_stats.hpp"

using Clock = std::chrono::steady_clock;

namespace
{

// Arrivals of the outputs of the frame in flight.
struct Arrivals
{
  std::mutex mutex;
  std::condition_variable cv;
  int count = 0;
  Clock::time_point last;
  bool have_stats = false;
  ring_curvature::FrameStats stats;
  void noteStats(const ring_curvature::FrameStats& s)
  {
    std::lock_guard<std::mutex> lock(mutex);
    stats = s;
    have_stats = true;
    cv.notify_all();
  }
  void note()
  {
    const auto now = Clock::now();
    std::lock_guard<std::mutex> lock(mutex);
    ++count;
    last = now;
    cv.notify_all();
  }
};

}  // namespace

int main(int argc, char** argv)
{
  ros::init(argc, argv, "ring_curvature_benchmark_nodelet", ros::init_options::NoSigintHandler);
  std::string bag_path, topic;
  int repeat = 20;
  for (int i = 1; i + 1 < argc; i += 2)
  {
    const std::string a = argv[i];
    if (a == "--bag")
      bag_path = argv[i + 1];
    else if (a == "--topic")
      topic = argv[i + 1];
    else if (a == "--repeat")
      repeat = std::max(1, std::atoi(argv[i + 1]));
    else
    {
      std::cerr << "benchmark_nodelet: unknown argument '" << a << "'\n";
      return 2;
    }
  }
  if (bag_path.empty())
  {
    std::cerr << "usage: benchmark_nodelet --bag IN.bag [--repeat N] [--topic T]\n";
    return 2;
  }
  if (!ros::master::check())
  {
    std::cerr << "benchmark_nodelet: no ROS master (run src/tools/benchmark_nodelet.sh, which starts one)\n";
    return 1;
  }

  std::vector<sensor_msgs::PointCloud2::ConstPtr> clouds;
  std::size_t total_points = 0;
  try
  {
    rosbag::Bag bag(bag_path, rosbag::bagmode::Read);
    rosbag::View view;
    if (topic.empty())
      view.addQuery(bag, rosbag::TypeQuery("sensor_msgs/PointCloud2"));
    else
      view.addQuery(bag, rosbag::TopicQuery(topic));
    for (const rosbag::MessageInstance& m : view)
      if (auto c = m.instantiate<sensor_msgs::PointCloud2>())
      {
        clouds.push_back(c);
        total_points += static_cast<std::size_t>(c->width) * c->height;
      }
  }
  catch (const std::exception& e)
  {
    std::cerr << "benchmark_nodelet: cannot read " << bag_path << ": " << e.what() << "\n";
    return 1;
  }
  if (clouds.empty())
  {
    std::cerr << "benchmark_nodelet: no PointCloud2 in " << bag_path << "\n";
    return 1;
  }

  ros::NodeHandle nh;
  ros::AsyncSpinner spinner(1);
  spinner.start();

  // A real manager: the loader owns the nodelet's callback queues and worker threads.
  nodelet::Loader loader(false);
  const std::string name = "/ring_curvature";
  if (!loader.load(name, "ring_curvature/RingCurvatureNodelet", nodelet::M_string(), nodelet::V_string()))
  {
    std::cerr << "benchmark_nodelet: cannot load ring_curvature/RingCurvatureNodelet (is the workspace sourced?)\n";
    return 1;
  }

  Arrivals arrivals;
  std::vector<ros::Subscriber> subs;
  // Exact message types, so that each subscription receives the published object itself
  // (a type-erased subscriber would force serialization and measure that instead).
  const boost::function<void(const sensor_msgs::PointCloud2ConstPtr&)> on_cloud =
      [&arrivals](const sensor_msgs::PointCloud2ConstPtr&) { arrivals.note(); };
  const boost::function<void(const ring_curvature::PrimitiveArrayConstPtr&)> on_primitives =
      [&arrivals](const ring_curvature::PrimitiveArrayConstPtr&) { arrivals.note(); };
  const boost::function<void(const visualization_msgs::MarkerArrayConstPtr&)> on_markers =
      [&arrivals](const visualization_msgs::MarkerArrayConstPtr&) { arrivals.note(); };
  subs.push_back(nh.subscribe<sensor_msgs::PointCloud2>(name + "/labelled_points", 1, on_cloud));
  subs.push_back(nh.subscribe<ring_curvature::PrimitiveArray>(name + "/primitives", 1, on_primitives));
  subs.push_back(nh.subscribe<sensor_msgs::PointCloud2>(name + "/edges", 1, on_cloud));
  subs.push_back(nh.subscribe<sensor_msgs::PointCloud2>(name + "/planes", 1, on_cloud));
  subs.push_back(nh.subscribe<visualization_msgs::MarkerArray>(name + "/markers", 1, on_markers));
  const int num_outputs = static_cast<int>(subs.size());
  // not an output: published after them, with the callback's own timing
  const boost::function<void(const ring_curvature::FrameStatsConstPtr&)> on_stats =
      [&arrivals](const ring_curvature::FrameStatsConstPtr& s) { arrivals.noteStats(*s); };
  subs.push_back(nh.subscribe<ring_curvature::FrameStats>(name + "/frame_stats", 1, on_stats));
  ros::Publisher pub = nh.advertise<sensor_msgs::PointCloud2>("velodyne_points", 1);
  const auto deadline = Clock::now() + std::chrono::seconds(10);
  while (pub.getNumSubscribers() == 0 && Clock::now() < deadline)
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  if (pub.getNumSubscribers() == 0)
  {
    std::cerr << "benchmark_nodelet: the nodelet never subscribed to velodyne_points\n";
    return 1;
  }

  std::vector<double> latency, callback, core, messages;
  // the core's stages as the nodelet timed them (~frame_stats), to set beside `benchmark`'s
  std::vector<double> stage[6];
  int lost = 0;
  for (int r = -1; r < repeat; ++r)  // r = -1: untimed warm-up pass
  {
    for (const auto& c : clouds)
    {
      Clock::time_point t0;
      {
        std::lock_guard<std::mutex> lock(arrivals.mutex);
        arrivals.count = 0;
        arrivals.have_stats = false;
      }
      t0 = Clock::now();
      pub.publish(c);
      std::unique_lock<std::mutex> lock(arrivals.mutex);
      if (!arrivals.cv.wait_for(lock, std::chrono::seconds(5),
                                [&] { return arrivals.count >= num_outputs && arrivals.have_stats; }))
      {
        ++lost;
        continue;
      }
      if (r >= 0)
      {
        const ring_curvature::FrameStats& st = arrivals.stats;
        latency.push_back(std::chrono::duration<double, std::milli>(arrivals.last - t0).count());
        callback.push_back(st.callback_ms);
        core.push_back(st.grid_ms + st.features_ms + st.thresholds_ms + st.classification_ms + st.primitives_ms +
                       st.core_output_ms);
        messages.push_back(st.messages_ms);
        const float times[6] = {st.grid_ms,           st.features_ms,   st.thresholds_ms,
                                st.classification_ms, st.primitives_ms, st.core_output_ms};
        for (int k = 0; k < 6; ++k) stage[k].push_back(times[k]);
      }
    }
  }
  loader.unload(name);
  spinner.stop();
  if (latency.empty())
  {
    std::cerr << "benchmark_nodelet: no frame produced all " << num_outputs << " outputs (" << lost << " lost)\n";
    return 1;
  }
  const double mean_points = static_cast<double>(total_points) / static_cast<double>(clouds.size());
  std::printf("ring_curvature nodelet benchmark: %s\n", bag_path.c_str());
  std::printf("  %zu frames, %.0f points/frame, repeat %d (+1 warm-up), %d outputs subscribed, %d frames lost\n",
              clouds.size(), mean_points, repeat, num_outputs, lost);
  std::printf("  publish -> last output [ms]: median %.3f, p90 %.3f, max %.3f\n",
              ring_curvature::bench::median(latency), ring_curvature::bench::quantile(latency, 0.9),
              ring_curvature::bench::quantile(latency, 1.0));
  std::printf("  callback entry -> last publish [ms] (~frame_stats): median %.3f, p90 %.3f, max %.3f\n",
              ring_curvature::bench::median(callback), ring_curvature::bench::quantile(callback, 0.9),
              ring_curvature::bench::quantile(callback, 1.0));
  std::printf("    of which core (grid .. output) median %.3f, output messages median %.3f\n",
              ring_curvature::bench::median(core), ring_curvature::bench::median(messages));
  std::printf("    core stages, medians: grid %.3f, features %.3f, thresholds %.3f, classification %.3f, "
              "primitives %.3f, output %.3f\n",
              ring_curvature::bench::median(stage[0]), ring_curvature::bench::median(stage[1]),
              ring_curvature::bench::median(stage[2]), ring_curvature::bench::median(stage[3]),
              ring_curvature::bench::median(stage[4]), ring_curvature::bench::median(stage[5]));
  std::printf("frames=%zu points=%.0f nodelet_ms=%.4f nodelet_p90_ms=%.4f callback_ms=%.4f callback_p90_ms=%.4f "
              "core_ms=%.4f messages_ms=%.4f\n",
              clouds.size(), mean_points, ring_curvature::bench::median(latency),
              ring_curvature::bench::quantile(latency, 0.9), ring_curvature::bench::median(callback),
              ring_curvature::bench::quantile(callback, 0.9), ring_curvature::bench::median(core),
              ring_curvature::bench::median(messages));
  ros::shutdown();
  return lost == 0 ? 0 : 1;
}
