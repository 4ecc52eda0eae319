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
#include <sensor_msgs/PointCloud2.h>
#include <visualization_msgs/MarkerArray.h>

#include "ring_curvature/FrameStats.h"
#include "ring_curvature/PrimitiveArray.h"

#include <algorithm>
#include <chrono>
#include <condition_variable>
#include <cstdio>
#include <cstdlib>
#include <iostream>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "bag_clouds.hpp"
#include "bench_stats.hpp"
#include "option_pairs.hpp"

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

struct Options
{
  std::string bag, topic;  // topic empty: every PointCloud2 topic
  int repeat = 20;
};

// False (the exit status is then 2) at an unknown argument or without --bag.
bool parseArgs(int argc, char** argv, Options& o)
{
  namespace bench = ring_curvature::bench;
  const auto repeat = [&o](const std::string& v) { o.repeat = std::max(1, std::atoi(v.c_str())); };
  if (!bench::readOptionPairs(argc, argv, "benchmark_nodelet",
                              {{"--bag", bench::into(o.bag)}, {"--topic", bench::into(o.topic)}, {"--repeat", repeat}}))
    return false;
  if (o.bag.empty())
  {
    std::cerr << "usage: benchmark_nodelet --bag IN.bag [--repeat N] [--topic T]\n";
    return false;
  }
  return true;
}

bool loadClouds(const Options& opt, std::vector<sensor_msgs::PointCloud2::ConstPtr>& clouds)
{
  try
  {
    clouds = ring_curvature::bench::readClouds(opt.bag, opt.topic);
  }
  catch (const std::exception& e)
  {
    std::cerr << "benchmark_nodelet: cannot read " << opt.bag << ": " << e.what() << "\n";
    return false;
  }
  if (clouds.empty())
  {
    std::cerr << "benchmark_nodelet: no PointCloud2 in " << opt.bag << "\n";
    return false;
  }
  return true;
}

// A subscriber on each of the nodelet's five outputs (so that it builds them all), counted as
// `num_outputs`, then one on ~frame_stats.
std::vector<ros::Subscriber> subscribe(ros::NodeHandle& nh, const std::string& name, Arrivals& arrivals,
                                       int& num_outputs)
{
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
  num_outputs = static_cast<int>(subs.size());
  // not an output: published after them, with the callback's own timing
  const boost::function<void(const ring_curvature::FrameStatsConstPtr&)> on_stats =
      [&arrivals](const ring_curvature::FrameStatsConstPtr& s) { arrivals.noteStats(*s); };
  subs.push_back(nh.subscribe<ring_curvature::FrameStats>(name + "/frame_stats", 1, on_stats));
  return subs;
}

// Waits up to 10 s for the nodelet to subscribe to its input.
bool waitForSubscriber(const ros::Publisher& pub)
{
  const auto deadline = Clock::now() + std::chrono::seconds(10);
  while (pub.getNumSubscribers() == 0 && Clock::now() < deadline)
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  if (pub.getNumSubscribers() == 0)
  {
    std::cerr << "benchmark_nodelet: the nodelet never subscribed to velodyne_points\n";
    return false;
  }
  return true;
}

// The timed frames' samples, and the frames whose outputs did not all arrive within 5 s.
struct Samples
{
  std::vector<double> latency, callback, core, messages;
  // the core's stages as the nodelet timed them (~frame_stats), to set beside `benchmark`'s
  std::vector<double> stage[6];
  int lost = 0;
};

// Publishes each cloud and waits for all its outputs, in `repeat` passes after an untimed one.
Samples timeFrames(const Options& opt, const std::vector<sensor_msgs::PointCloud2::ConstPtr>& clouds,
                   ros::Publisher& pub, Arrivals& arrivals, int num_outputs)
{
  Samples s;
  for (int r = -1; r < opt.repeat; ++r)  // r = -1: untimed warm-up pass
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
        ++s.lost;
        continue;
      }
      if (r >= 0)
      {
        const ring_curvature::FrameStats& st = arrivals.stats;
        s.latency.push_back(std::chrono::duration<double, std::milli>(arrivals.last - t0).count());
        s.callback.push_back(st.callback_ms);
        s.core.push_back(st.grid_ms + st.features_ms + st.thresholds_ms + st.classification_ms + st.primitives_ms +
                         st.core_output_ms);
        s.messages.push_back(st.messages_ms);
        const float times[6] = {st.grid_ms,           st.features_ms,   st.thresholds_ms,
                                st.classification_ms, st.primitives_ms, st.core_output_ms};
        for (int k = 0; k < 6; ++k) s.stage[k].push_back(times[k]);
      }
    }
  }
  return s;
}

void printReport(const Options& opt, std::size_t frames, double mean_points, int num_outputs, const Samples& s)
{
  namespace bench = ring_curvature::bench;
  std::printf("ring_curvature nodelet benchmark: %s\n", opt.bag.c_str());
  std::printf("  %zu frames, %.0f points/frame, repeat %d (+1 warm-up), %d outputs subscribed, %d frames lost\n",
              frames, mean_points, opt.repeat, num_outputs, s.lost);
  std::printf("  publish -> last output [ms]: median %.3f, p90 %.3f, max %.3f\n", bench::median(s.latency),
              bench::quantile(s.latency, 0.9), bench::quantile(s.latency, 1.0));
  std::printf("  callback entry -> last publish [ms] (~frame_stats): median %.3f, p90 %.3f, max %.3f\n",
              bench::median(s.callback), bench::quantile(s.callback, 0.9), bench::quantile(s.callback, 1.0));
  std::printf("    of which core (grid .. output) median %.3f, output messages median %.3f\n", bench::median(s.core),
              bench::median(s.messages));
  std::printf("    core stages, medians: grid %.3f, features %.3f, thresholds %.3f, classification %.3f, "
              "primitives %.3f, output %.3f\n",
              bench::median(s.stage[0]), bench::median(s.stage[1]), bench::median(s.stage[2]),
              bench::median(s.stage[3]), bench::median(s.stage[4]), bench::median(s.stage[5]));
  std::printf("frames=%zu points=%.0f nodelet_ms=%.4f nodelet_p90_ms=%.4f callback_ms=%.4f callback_p90_ms=%.4f "
              "core_ms=%.4f messages_ms=%.4f\n",
              frames, mean_points, bench::median(s.latency), bench::quantile(s.latency, 0.9),
              bench::median(s.callback), bench::quantile(s.callback, 0.9), bench::median(s.core),
              bench::median(s.messages));
}

}  // namespace

int main(int argc, char** argv)
{
  ros::init(argc, argv, "ring_curvature_benchmark_nodelet", ros::init_options::NoSigintHandler);
  Options opt;
  if (!parseArgs(argc, argv, opt))
    return 2;
  if (!ros::master::check())
  {
    std::cerr << "benchmark_nodelet: no ROS master (run src/tools/benchmark_nodelet.sh, which starts one)\n";
    return 1;
  }
  std::vector<sensor_msgs::PointCloud2::ConstPtr> clouds;
  if (!loadClouds(opt, clouds))
    return 1;
  std::size_t total_points = 0;
  for (const auto& c : clouds)
    total_points += static_cast<std::size_t>(c->width) * c->height;

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
  int num_outputs = 0;
  const std::vector<ros::Subscriber> subs = subscribe(nh, name, arrivals, num_outputs);
  ros::Publisher pub = nh.advertise<sensor_msgs::PointCloud2>("velodyne_points", 1);
  if (!waitForSubscriber(pub))
    return 1;

  const Samples samples = timeFrames(opt, clouds, pub, arrivals, num_outputs);
  loader.unload(name);
  spinner.stop();
  if (samples.latency.empty())
  {
    std::cerr << "benchmark_nodelet: no frame produced all " << num_outputs << " outputs (" << samples.lost
              << " lost)\n";
    return 1;
  }
  const double mean_points = static_cast<double>(total_points) / static_cast<double>(clouds.size());
  printReport(opt, clouds.size(), mean_points, num_outputs, samples);
  ros::shutdown();
  return samples.lost == 0 ? 0 : 1;
}
