// rosrun ring_curvature benchmark --bag IN.bag [--repeat N] [--baselines] [--baseline-repeat M]
//                                 [--topic T] [--euclid-tolerance METRES] [--params FILE.yaml]
// Times every stage of the core pipeline over every PointCloud2 frame of a bag, N times, and with
// --baselines also PCL's PCA curvature (k = 10) and Euclidean clustering on the same frames in the
// same process. --params: the core's parameters from a flat 'key: value' file (the keys of
// config/ring_curvature.yaml, as process_bag takes them), defaults otherwise. Prints a table of
// medians; the LAST line is machine-readable key=value pairs:
//   frames=… points=… pipeline_ms=… pca_curv_ms=… euclid_ms=… speedup_pca=… loam_ms=…
// (loam_ms: the LOAM feature sets of the SLAM front end, selected after the pipeline, not in it)
#include <sensor_msgs/PointCloud2.h>

#include <array>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <iostream>
#include <string>
#include <vector>

#include "bag_clouds.hpp"
#include "bench_stats.hpp"
#include "fnv_hash.hpp"
#include "baselines/euclidean_clustering.hpp"
#include "baselines/pca_curvature.hpp"
#include "ring_curvature/pipeline.hpp"
#include "ring_curvature/ros/cloud_adapter.hpp"
#include "ring_curvature/ros/param_loading.hpp"

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
  std::string params_file;  // empty: the defaults
  rc::Params params;
};

void usage()
{
  std::cerr << "usage: benchmark --bag IN.bag [--repeat N] [--baselines] [--baseline-repeat M]"
               " [--topic T] [--euclid-tolerance M] [--params FILE.yaml]\n";
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
    if (a == "--params" && value(o.params_file))
    {
      const rc::Status st = rc::loadParamsFile(o.params_file, o.params);
      if (st)
        continue;
      std::cerr << "benchmark: " << st.message << "\n";
      return false;
    }
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

// Every PointCloud2 of the bag, read before any timing so that bag I/O is never inside a timed
// region.
bool loadClouds(const Options& opt, std::vector<sensor_msgs::PointCloud2::ConstPtr>& clouds)
{
  try
  {
    clouds = rc::bench::readClouds(opt.bag, opt.topic);
  }
  catch (const std::exception& e)
  {
    std::cerr << "benchmark: cannot read " << opt.bag << ": " << e.what() << "\n";
    return false;
  }
  return true;
}

// The clouds as the core reads them (views into the messages, which must outlive them); false
// when none is usable.
bool makeViews(const Options& opt, const std::vector<sensor_msgs::PointCloud2::ConstPtr>& clouds,
               std::vector<rc::PointCloudView>& views, std::size_t& total_points)
{
  for (const auto& c : clouds)
  {
    rc::PointCloudView v;
    // the nodelet's own adapter: the benchmark reads clouds exactly as the nodelet does
    const rc::Status st = rc::makeView(*c, opt.params, v);
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
    return false;
  }
  return true;
}

// Every sample of every timed row, and the labels and primitives of the first timed pass.
struct Timings
{
  std::vector<double> grid, features, thresholds, classification, primitives, output, stage_sum, wall, loam;
  std::vector<double> pca, euclid;
  std::size_t primitive_count = 0;
  std::array<std::size_t, rc::kNumLabels> counts{};
  // the LOAM sets and sweep times of the last pass, so that two builds (a restructured selection
  // against the old one) can be shown to choose the same points
  std::uint64_t loam_digest = rc::bench::kFnvOffsetBasis;
};

// Our pipeline: one untimed warm-up pass (buffers grow to size), then `repeat` passes.
bool timePipeline(const Options& opt, const std::vector<rc::PointCloudView>& views, rc::Pipeline& pipeline,
                  rc::FrameResult& result, Timings& t)
{
  for (const auto& v : views)
  {
    const rc::Status st = pipeline.process(v, result);
    if (!st)
    {
      std::cerr << "benchmark: pipeline rejected a frame: " << st.message << "\n";
      return false;
    }
  }
  for (int r = 0; r < opt.repeat; ++r)
  {
    for (const auto& v : views)
    {
      const auto t0 = Clock::now();
      pipeline.process(v, result);
      t.wall.push_back(msSince(t0));
      const rc::StageTimes& st = result.times;
      t.grid.push_back(st.grid);
      t.features.push_back(st.features);
      t.thresholds.push_back(st.thresholds);
      t.classification.push_back(st.classification);
      t.primitives.push_back(st.primitives);
      t.output.push_back(st.output);
      t.stage_sum.push_back(st.total());
      if (r == 0)
      {
        t.primitive_count += result.primitives.primitives.size();
        for (int l = 0; l < rc::kNumLabels; ++l)
          t.counts[l] += result.label_counts[l];
      }
    }
  }
  return true;
}

// The LOAM sets, in passes of their own: between the pipeline's runs they would change what the
// caches hold when the next one starts.
void timeLoam(const Options& opt, const std::vector<rc::PointCloudView>& views, rc::Pipeline& pipeline,
              rc::FrameResult& result, Timings& t)
{
  rc::LoamFeatures loam;  // the SLAM front end's sets, chosen from the grid's labels as the nodelet does
  for (int r = 0; r < opt.repeat; ++r)
  {
    for (const auto& v : views)
    {
      pipeline.process(v, result, rc::Pipeline::Scope::GridLabels);
      const auto tl = Clock::now();
      pipeline.selectLoamFeatures(v, loam);
      t.loam.push_back(msSince(tl));
      if (r + 1 < opt.repeat) continue;
      for (const auto* set : {&loam.sharp, &loam.less_sharp, &loam.flat, &loam.less_flat})
      {
        const std::uint64_t n = set->size();  // (where one set ends and the next begins)
        rc::bench::hashBytes(t.loam_digest, &n, sizeof n);
        rc::bench::hashVector(t.loam_digest, *set);
      }
      rc::bench::hashVector(t.loam_digest, loam.sweep_time);
    }
  }
}

// PCL baselines on the same frames, same process.
void timeBaselines(const Options& opt, const std::vector<rc::PointCloudView>& views, Timings& t)
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
      t.pca.push_back(msSince(t0));
      t0 = Clock::now();
      euclid.label(v, labels);
      t.euclid.push_back(msSince(t0));
    }
  }
}

void printHeader(const Options& opt, std::size_t frames, double mean_points, const Timings& t)
{
  std::printf("ring_curvature benchmark: %s\n", opt.bag.c_str());
  std::printf("  cpu: %s; single thread, Release; core loops: %s\n", cpuModel().c_str(),
              ring_curvature::coreLoopsIsa());
  const std::string baselines_note =
      opt.baselines ? ", baselines repeat " + std::to_string(opt.baseline_repeat) + ", euclid tolerance " +
                          std::to_string(static_cast<int>(opt.euclid_tolerance * 100.0f + 0.5f)) + " cm"
                    : "";
  std::printf("  %zu frames, %.0f points/frame (mean), repeat %d (+1 warm-up)%s\n", frames, mean_points, opt.repeat,
              baselines_note.c_str());
  std::printf("  params: %s\n", opt.params_file.empty() ? "defaults" : opt.params_file.c_str());
  const double nf = static_cast<double>(frames);
  auto perFrame = [nf](std::size_t c) { return static_cast<double>(c) / nf; };
  std::printf("  labels/frame: plane %.0f, edge %.0f, corner %.0f, rough %.0f, none %.0f; primitives/frame %.1f\n",
              perFrame(t.counts[1]), perFrame(t.counts[2]), perFrame(t.counts[3]), perFrame(t.counts[4]),
              perFrame(t.counts[0]), perFrame(t.primitive_count));
}

// The table of medians, then the machine-readable last line.
void printTimes(const Options& opt, std::size_t frames, double mean_points, const Timings& t)
{
  std::printf("  %-16s %10s %10s %10s\n", "stage [ms]", "median", "p90", "max");
  printRow("grid", t.grid);
  printRow("features", t.features);
  printRow("thresholds", t.thresholds);
  printRow("classification", t.classification);
  printRow("primitives", t.primitives);
  printRow("output", t.output);
  printRow("sum of stages", t.stage_sum);
  printRow("pipeline (wall)", t.wall);
  printRow("LOAM sets", t.loam);
  std::printf("  LOAM sets digest (FNV-1a of the sets and sweep times): %016llx\n",
              static_cast<unsigned long long>(t.loam_digest));
  const double pipeline_ms = rc::bench::median(t.wall);
  double pca_ms = std::nan(""), euclid_ms = std::nan(""), speedup = std::nan("");
  if (opt.baselines)
  {
    printRow("PCL PCA-Curv", t.pca);
    printRow("PCL Euclidean", t.euclid);
    pca_ms = rc::bench::median(t.pca);
    euclid_ms = rc::bench::median(t.euclid);
    speedup = pca_ms / pipeline_ms;
  }
  std::printf("frames=%zu points=%.0f pipeline_ms=%.4f pca_curv_ms=%.3f euclid_ms=%.3f speedup_pca=%.1f loam_ms=%.4f\n",
              frames, mean_points, pipeline_ms, pca_ms, euclid_ms, speedup, rc::bench::median(t.loam));
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
  std::vector<sensor_msgs::PointCloud2::ConstPtr> clouds;
  std::vector<rc::PointCloudView> views;
  std::size_t total_points = 0;
  if (!loadClouds(opt, clouds) || !makeViews(opt, clouds, views, total_points))
    return 1;
  const double mean_points = static_cast<double>(total_points) / static_cast<double>(views.size());

  // one pipeline for both: the LOAM passes start from the caches the timed passes left
  rc::Pipeline pipeline(opt.params);
  rc::FrameResult result;
  Timings t;
  if (!timePipeline(opt, views, pipeline, result, t))
    return 1;
  timeLoam(opt, views, pipeline, result, t);
  if (opt.baselines)
    timeBaselines(opt, views, t);

  printHeader(opt, views.size(), mean_points, t);
  printTimes(opt, views.size(), mean_points, t);
  return 0;
}
