// Offline run of the nodelet's code path over a bag:
//   process_bag --input IN.bag --output OUT.bag [--topic /velodyne_points] [--params FILE.yaml]
//               [--times-csv FILE]
// Writes what the nodelet would publish, under the topics it would publish them on, with the
// input messages' bag times. Needs no roscore.
#include <rosbag/bag.h>
#include <rosbag/view.h>
#include <ros/time.h>

#include <unistd.h>

#include <array>
#include <chrono>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <string>

#include "ring_curvature/PrimitiveArray.h"
#include "ring_curvature/ros/frame_processor.hpp"
#include "ring_curvature/ros/param_loading.hpp"

namespace
{

const char* const kUsage =
    "usage: process_bag --input IN.bag --output OUT.bag [--topic /velodyne_points] [--params FILE.yaml]\n"
    "                   [--times-csv FILE]\n"
    "  Runs ring_curvature on every sensor_msgs/PointCloud2 on --topic and writes\n"
    "  /ring_curvature/{labelled_points,primitives,edges,planes,markers} to OUT.bag.\n"
    "  --params: a flat 'key: value' file with the keys of config/ring_curvature.yaml.\n"
    "  --times-csv: one row per processed frame with the core's stage times in ms (Figure 7).\n";

struct Options
{
  std::string input, output, topic = "/velodyne_points", params, times_csv;
};

bool parseArgs(int argc, char** argv, Options& o)
{
  for (int i = 1; i < argc; ++i)
  {
    const std::string a = argv[i];
    if (a == "-h" || a == "--help")
      return false;
    if (i + 1 >= argc)
    {
      std::cerr << "process_bag: " << a << " needs a value\n";
      return false;
    }
    const std::string v = argv[++i];
    if (a == "--input")
      o.input = v;
    else if (a == "--output")
      o.output = v;
    else if (a == "--topic")
      o.topic = v;
    else if (a == "--params")
      o.params = v;
    else if (a == "--times-csv")
      o.times_csv = v;
    else
    {
      std::cerr << "process_bag: unknown option " << a << "\n";
      return false;
    }
  }
  if (o.input.empty() || o.output.empty())
  {
    std::cerr << "process_bag: --input and --output are required\n";
    return false;
  }
  return true;
}

void progress(std::size_t done, std::size_t total)
{
  const int width = 40;
  const int filled = total ? static_cast<int>(width * done / total) : width;
  std::fprintf(stdout, "\r[%.*s%*s] %zu/%zu", filled, "========================================", width - filled,
               "", done, total);
  std::fflush(stdout);
}

// Totals over the frames processed, for the summary line.
struct Totals
{
  std::size_t frames = 0, rejected = 0, points = 0, primitives = 0;
  std::array<std::size_t, ring_curvature::kNumLabels> labels{};
  double core_ms = 0, total_ms = 0;

  void add(const ring_curvature::FrameSummary& f, double ms)
  {
    ++frames;
    points += f.points;
    primitives += f.primitives;
    for (int l = 0; l < ring_curvature::kNumLabels; ++l)
      labels[l] += f.label_counts[l];
    core_ms += f.coreMs();
    total_ms += ms;
  }
};

// Per-frame stage times for the runtime figure; the summary line only has the mean.
bool openTimesCsv(const std::string& path, std::ofstream& times)
{
  times.open(path);
  if (!times)
  {
    std::cerr << "process_bag: cannot write " << path << "\n";
    return false;
  }
  times << "frame,points,grid_ms,features_ms,thresholds_ms,classification_ms,primitives_ms,core_output_ms,"
           "core_ms,messages_ms\n";
  return true;
}

void writeTimesRow(std::ofstream& times, std::size_t frame, const ring_curvature::FrameSummary& f)
{
  times << frame << ',' << f.points << ',' << f.grid_ms << ',' << f.features_ms << ',' << f.thresholds_ms << ','
        << f.classification_ms << ',' << f.primitives_ms << ',' << f.core_output_ms << ',' << f.coreMs() << ','
        << f.messages_ms << '\n';
}

// The topics the nodelet publishes on, stamped with the input message's bag time.
void writeOutputs(rosbag::Bag& out, const ros::Time& t, const ring_curvature::Outputs& o)
{
  out.write("/ring_curvature/labelled_points", t, *o.labelled);
  out.write("/ring_curvature/primitives", t, *o.primitives);
  out.write("/ring_curvature/edges", t, *o.edges);
  out.write("/ring_curvature/planes", t, *o.planes);
  out.write("/ring_curvature/markers", t, *o.markers);
}

// One input message, the `frame`-th on the topic: processed and written, or counted as rejected.
// True when its outputs were written.
bool processMessage(const rosbag::MessageInstance& m, std::size_t frame, const std::string& topic,
                    ring_curvature::FrameProcessor& processor, rosbag::Bag& out, std::ofstream& times, Totals& totals)
{
  const auto cloud = m.instantiate<sensor_msgs::PointCloud2>();
  if (!cloud)
  {
    std::cerr << "\nprocess_bag: skipping a " << m.getDataType() << " message on " << topic << "\n";
    ++totals.rejected;
    return false;
  }
  ring_curvature::Outputs o;
  const auto t0 = std::chrono::steady_clock::now();
  const auto s = processor.process(*cloud, o);
  const double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
  if (!s)
  {
    std::cerr << "\nprocess_bag: frame " << frame << " (stamp " << cloud->header.stamp << ") rejected: " << s.message
              << "\n";
    ++totals.rejected;
    return false;
  }
  const auto& f = processor.summary();
  totals.add(f, ms);
  if (times.is_open())
    writeTimesRow(times, frame, f);
  writeOutputs(out, m.getTime(), o);
  return true;
}

void printSummary(const Totals& t)
{
  std::size_t counted = 0;
  for (int l = 0; l < ring_curvature::kNumLabels; ++l)
    counted += t.labels[l];
  auto share = [&](ring_curvature::Label l) {
    return counted ? 100.0 * static_cast<double>(t.labels[static_cast<int>(l)]) / static_cast<double>(counted) : 0.0;
  };
  std::printf("process_bag: %zu frames (%zu rejected), %zu points, labels none %.1f%% plane %.1f%% edge %.1f%% "
              "corner %.1f%% rough %.1f%%, %zu primitives, mean %.2f ms/frame (core %.2f ms)\n",
              t.frames, t.rejected, t.points, share(ring_curvature::Label::None), share(ring_curvature::Label::Plane),
              share(ring_curvature::Label::Edge), share(ring_curvature::Label::Corner),
              share(ring_curvature::Label::Rough), t.primitives,
              t.frames ? t.total_ms / static_cast<double>(t.frames) : 0.0,
              t.frames ? t.core_ms / static_cast<double>(t.frames) : 0.0);
}

// Every message on the topic through the processor into the output bag, then the summary line.
// Returns the exit status.
int run(const Options& opt, ring_curvature::FrameProcessor& processor)
{
  try
  {
    rosbag::Bag in(opt.input, rosbag::bagmode::Read);
    rosbag::View view(in, rosbag::TopicQuery(opt.topic));
    const std::size_t total = view.size();
    if (total == 0)
    {
      std::cerr << "process_bag: no messages on topic " << opt.topic << " in " << opt.input << "\n";
      return 1;
    }
    rosbag::Bag out(opt.output, rosbag::bagmode::Write);
    const bool tty = isatty(STDOUT_FILENO) != 0;
    std::ofstream times;
    if (!opt.times_csv.empty() && !openTimesCsv(opt.times_csv, times))
      return 1;
    Totals totals;
    std::size_t done = 0;
    for (const rosbag::MessageInstance& m : view)
    {
      ++done;
      if (processMessage(m, done, opt.topic, processor, out, times, totals) && tty)
        progress(done, total);
    }
    out.close();
    if (tty)
      std::fputc('\n', stdout);
    printSummary(totals);
    return totals.frames > 0 ? 0 : 1;
  }
  catch (const std::exception& e)
  {
    std::cerr << "process_bag: " << e.what() << "\n";
    return 1;
  }
}

}  // namespace

int main(int argc, char** argv)
{
  Options opt;
  if (!parseArgs(argc, argv, opt))
  {
    std::cerr << kUsage;
    return 2;
  }
  ros::Time::init();

  ring_curvature::Params params;
  if (!opt.params.empty())
  {
    const auto s = ring_curvature::loadParamsFile(opt.params, params);
    if (!s)
    {
      std::cerr << "process_bag: " << s.message << "\n";
      return 2;
    }
  }
  ring_curvature::FrameProcessor processor(params);
  return run(opt, processor);
}
