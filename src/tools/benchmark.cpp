// rosrun ring_curvature benchmark --bag IN.bag [--repeat N] [--baselines] [--baseline-repeat M]
//                                 [--topic T] [--euclid-tolerance METRES]
// Times every stage of the core pipeline over every PointCloud2 frame of a bag, N times, and with
// --baselines also PCL's PCA curvature (k = 10) and Euclidean clustering on the same frames in the
// same process. Prints a table of medians; the LAST line is machine-readable key=value pairs:
//   frames=… points=… pipeline_ms=… pca_curv_ms=… euclid_ms=… speedup_pca=… loam_ms=…
// (loam_ms: the LOAM feature sets of the SLAM front end, selected after the pipeline, not in it)
#include <rosbag/bag.h>
#include <rosbag/query.h>
#include <rosbag/view.h>
#include <sensor_msgs/PointCloud2.h>

#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <iostream>
#include <string>
#include <vector>

#include "bench_stats.hpp"
#include "baselines/euclidean_clustering.hpp"
#include "baselines/pca_curvature.hpp"
#include "ring_curvature/pipeline.hpp"
#include "ring_curvature/ros/cloud_adapter.hpp"

namespace rc = ring_curvature;
using Clock = std::chrono::steady_clock;

namespace
{

struct Options
{
  std::string bag;
  std::string topic;  // empty: every PointCloud2 topic
  int repeat = 20;
  int baseline_repeat = 3;  // PCL is ~50x slower: fewer passes keep the run short
  bool baselines = false;
  float euclid_tolerance = rc::baselines::EuclideanClusteringParams().tolerance;
};

void usage()
{
  std::cerr << "usage: benchmark --bag IN.bag [--repeat N] [--baselines] [--baseline-repeat M]"
               " [--topic T] [--euclid-tolerance M]\n";
}

bool parseArgs(int argc, char** argv, Options& o)
{
  for (int i = 1; i < argc; ++i)
  {
    const std::string a = argv[i];
    auto value = [&](std::string& out) {
      if (i + 1 >= argc)
        return false;
      out = argv[++i];
      return true;
    };
    std::string v;
    if (a == "--bag" && value(o.bag))
      continue;
    if (a == "--topic" && value(o.topic))
      continue;
    if (a == "--repeat" && value(v) && (o.repeat = std::atoi(v.c_str())) > 0)
      continue;
    if (a == "--baseline-repeat" && value(v) && (o.baseline_repeat = std::atoi(v.c_str())) > 0)
      continue;
    if (a == "--euclid-tolerance" && value(v) && (o.euclid_tolerance = std::strtof(v.c_str(), nullptr)) > 0)
      continue;
    if (a == "--baselines")
    {
      o.baselines = true;
      continue;
    }
    if (a == "-h" || a == "--help")
      return false;
    std::cerr << "benchmark: bad or incomplete argument '" << a << "'\n";
    return false;
  }
  if (o.bag.empty())
    std::cerr << "benchmark: --bag is required\n";
  return !o.bag.empty();
}

std::string cpuModel()
{
  std::ifstream in("/proc/cpuinfo");
  std::string line;
  while (std::getline(in, line))
    if (line.rfind("model name", 0) == 0)
      return line.substr(line.find(':') + 2);
  return "unknown";
}

double msSince(Clock::time_point t0)
{
  return std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
}

void printRow(const char* name, const std::vector<double>& v)
{
  std::printf("  %-16s %10.3f %10.3f %10.3f\n", name, rc::bench::median(v), rc::bench::quantile(v, 0.9),
              rc::bench::quantile(v, 1.0));
}

}  // namespace

int main(int argc, char** argv)
{
  Options opt;
  if (!parseArgs(argc, argv, opt))
  {
    usage();
    return 2;
  }

  // Load every frame first so that bag I/O is never inside a timed region.
  std::vector<sensor_msgs::PointCloud2::ConstPtr> clouds;
  try
  {
    rosbag::Bag bag(opt.bag, rosbag::bagmode::Read);
    rosbag::View query;
    if (opt.topic.empty())
      query.addQuery(bag, rosbag::TypeQuery("sensor_msgs/PointCloud2"));
    else
      query.addQuery(bag, rosbag::TopicQuery(opt.topic));
    for (const rosbag::MessageInstance& m : query)
      if (auto c = m.instantiate<sensor_msgs::PointCloud2>())
        clouds.push_back(c);
  }
  catch (const std::exception& e)
  {
    std::cerr << "benchmark: cannot read " << opt.bag << ": " << e.what() << "\n";
    return 1;
  }
  std::vector<rc::PointCloudView> views;
  std::size_t total_points = 0;
  for (const auto& c : clouds)
  {
    rc::PointCloudView v;
    // the nodelet's own adapter: the benchmark reads clouds exactly as the nodelet does
    const rc::Status st = rc::makeView(*c, rc::Params(), v);
    if (!st)
    {
      std::cerr << "benchmark: skipping a frame: " << st.message << "\n";
      continue;
    }
    views.push_back(v);
    total_points += v.size();
  }
  if (views.empty())
  {
    std::cerr << "benchmark: no usable PointCloud2 frames in " << opt.bag
              << (opt.topic.empty() ? "" : " on " + opt.topic) << "\n";
    return 1;
  }
  const double mean_points = static_cast<double>(total_points) / static_cast<double>(views.size());

  // --- our pipeline: one untimed warm-up pass (buffers grow to size), then `repeat` passes.
  rc::Pipeline pipeline;
  rc::FrameResult result;
  for (const auto& v : views)
  {
    const rc::Status st = pipeline.process(v, result);
    if (!st)
    {
      std::cerr << "benchmark: pipeline rejected a frame: " << st.message << "\n";
      return 1;
    }
  }
  std::vector<double> t_grid, t_feat, t_thr, t_cls, t_prim, t_out, t_stage_sum, t_wall, t_loam;
  rc::LoamFeatures loam;  // the SLAM front end's sets, chosen from the grid's labels as the nodelet does
  std::size_t primitives = 0;
  std::array<std::size_t, rc::kNumLabels> counts{};
  for (int r = 0; r < opt.repeat; ++r)
  {
    for (const auto& v : views)
    {
      const auto t0 = Clock::now();
      pipeline.process(v, result);
      t_wall.push_back(msSince(t0));
      const rc::StageTimes& t = result.times;
      t_grid.push_back(t.grid);
      t_feat.push_back(t.features);
      t_thr.push_back(t.thresholds);
      t_cls.push_back(t.classification);
      t_prim.push_back(t.primitives);
      t_out.push_back(t.output);
      t_stage_sum.push_back(t.total());
      if (r == 0)
      {
        primitives += result.primitives.primitives.size();
        for (int l = 0; l < rc::kNumLabels; ++l)
          counts[l] += result.label_counts[l];
      }
    }
  }

  // --- the LOAM sets, in passes of their own: between the pipeline's runs they would change
  // what the caches hold when the next one starts.
  for (int r = 0; r < opt.repeat; ++r)
  {
    for (const auto& v : views)
    {
      pipeline.process(v, result, rc::Pipeline::Scope::GridLabels);
      const auto tl = Clock::now();
      pipeline.selectLoamFeatures(v, loam);
      t_loam.push_back(msSince(tl));
    }
  }

  // --- PCL baselines on the same frames, same process.
  std::vector<double> t_pca, t_euclid;
  if (opt.baselines)
  {
    rc::baselines::PcaCurvature pca;
    rc::baselines::EuclideanClusteringParams ep;
    ep.tolerance = opt.euclid_tolerance;
    rc::baselines::EuclideanClustering euclid(ep);
    std::vector<std::uint8_t> labels;
    for (int r = 0; r < opt.baseline_repeat; ++r)
    {
      for (const auto& v : views)
      {
        auto t0 = Clock::now();
        pca.label(v, labels);
        t_pca.push_back(msSince(t0));
        t0 = Clock::now();
        euclid.label(v, labels);
        t_euclid.push_back(msSince(t0));
      }
    }
  }

  std::printf("ring_curvature benchmark: %s\n", opt.bag.c_str());
  std::printf("  cpu: %s; single thread, Release; core loops: %s\n", cpuModel().c_str(),
              ring_curvature::coreLoopsIsa());
  std::printf("  %zu frames, %.0f points/frame (mean), repeat %d (+1 warm-up)%s\n", views.size(), mean_points,
              opt.repeat, opt.baselines ? (", baselines repeat " + std::to_string(opt.baseline_repeat) +
                                  ", euclid tolerance " + std::to_string(static_cast<int>(opt.euclid_tolerance * 100.0f + 0.5f)) + " cm").c_str()
                             : "");
  const double nf = static_cast<double>(views.size());
  auto perFrame = [nf](std::size_t c) { return static_cast<double>(c) / nf; };
  std::printf("  labels/frame: plane %.0f, edge %.0f, corner %.0f, rough %.0f, none %.0f; primitives/frame %.1f\n",
              perFrame(counts[1]), perFrame(counts[2]), perFrame(counts[3]), perFrame(counts[4]),
              perFrame(counts[0]), perFrame(primitives));
  std::printf("  %-16s %10s %10s %10s\n", "stage [ms]", "median", "p90", "max");
  printRow("grid", t_grid);
  printRow("features", t_feat);
  printRow("thresholds", t_thr);
  printRow("classification", t_cls);
  printRow("primitives", t_prim);
  printRow("output", t_out);
  printRow("sum of stages", t_stage_sum);
  printRow("pipeline (wall)", t_wall);
  printRow("LOAM sets", t_loam);
  const double pipeline_ms = rc::bench::median(t_wall);
  double pca_ms = std::nan(""), euclid_ms = std::nan(""), speedup = std::nan("");
  if (opt.baselines)
  {
    printRow("PCL PCA-Curv", t_pca);
    printRow("PCL Euclidean", t_euclid);
    pca_ms = rc::bench::median(t_pca);
    euclid_ms = rc::bench::median(t_euclid);
    speedup = pca_ms / pipeline_ms;
  }
  std::printf("frames=%zu points=%.0f pipeline_ms=%.4f pca_curv_ms=%.3f euclid_ms=%.3f speedup_pca=%.1f loam_ms=%.4f\n",
              views.size(), mean_points, pipeline_ms, pca_ms, euclid_ms, speedup, rc::bench::median(t_loam));
  return 0;
}
