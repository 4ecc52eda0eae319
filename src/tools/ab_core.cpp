// ab_core --a-core LIB --a-shim SHIM --b-core LIB --b-shim SHIM --bag IN.bag
//         [--rounds R] [--passes P] [--topic T] [--a-env NAME=VALUE] [--b-env NAME=VALUE]
// Times two builds of the core in ONE process, frame by frame on the same frames: each build's
// libring_curvature_core.so is loaded with its shim (ab_shim.cpp compiled against that build's
// headers) into a link namespace of its own (dlmopen), so the two same-named libraries and their
// same-named symbols never meet. On a shared machine the speed can drift by up to 1.75x within
// minutes; running the two builds' benchmark binaries one after the other
// (bench_compare.sh) lets that drift into the comparison, alternating them frame by frame does
// not: the two calls of a pair are milliseconds apart. Prints per build the median of each stage
// and of the whole call, and the ratio B/A as the median over rounds of each round's median of
// frame-pair ratios, with its 10-90 % range; the same for the thread's CPU time of the call,
// which leaves out the time the thread waits descheduled while other processes run.
// --a-env / --b-env (each may be repeated) set a variable for that build's first frame only:
// a core that reads a switch from the environment once, at its first call, can so be timed
// against itself with the switch set on one side (the same folder as A and B:
// each side is a copy of its own in its own namespace).
// Loading a build and timing a call: ab_build.cpp; the frames in the shim's layout: ab_frames.cpp.
// src/tools/ab_core.sh builds the shims and runs it. The LAST line is machine-readable:
//   frames=… points=… pairs=… a_ms=… b_ms=… ratio=… ratio_p10=… ratio_p90=…
//   cpu_ratio=… cpu_ratio_p10=… cpu_ratio_p90=… outputs=same|DIFFERENT   (one line)
#include <sensor_msgs/PointCloud2.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <iostream>
#include <string>
#include <vector>

#include "ab_build.hpp"
#include "ab_frames.hpp"
#include "ab_shim.h"

namespace ab = ring_curvature::ab;

namespace
{

struct Options
{
  std::string core[2], shim[2];
  std::string bag, topic;
  int rounds = 20;
  int passes = 10;  // passes over the bag's frames per round
  std::vector<std::string> env[2];  // NAME=VALUE set for that build's first call
};

void usage()
{
  std::cerr << "usage: ab_core --a-core LIB --a-shim SHIM --b-core LIB --b-shim SHIM --bag IN.bag"
               " [--rounds R] [--passes P] [--topic T] [--a-env NAME=VALUE] [--b-env NAME=VALUE]\n";
}

bool parseArgs(int argc, char** argv, Options& o)
{
  for (int i = 1; i < argc; ++i)
  {
    const std::string a = argv[i];
    if (i + 1 >= argc)
    {
      std::cerr << "ab_core: bad or incomplete argument '" << a << "'\n";
      return false;
    }
    const std::string v = argv[++i];
    if (a == "--a-core")
      o.core[0] = v;
    else if (a == "--b-core")
      o.core[1] = v;
    else if (a == "--a-shim")
      o.shim[0] = v;
    else if (a == "--b-shim")
      o.shim[1] = v;
    else if (a == "--bag")
      o.bag = v;
    else if (a == "--topic")
      o.topic = v;
    else if ((a == "--a-env" || a == "--b-env") && v.find('=') != std::string::npos && v.find('=') > 0)
      o.env[a == "--a-env" ? 0 : 1].push_back(v);
    else if (a == "--rounds" && (o.rounds = std::atoi(v.c_str())) > 0)
      continue;
    else if (a == "--passes" && (o.passes = std::atoi(v.c_str())) > 0)
      continue;
    else
    {
      std::cerr << "ab_core: bad argument '" << a << " " << v << "'\n";
      return false;
    }
  }
  for (const std::string* s : {&o.core[0], &o.core[1], &o.shim[0], &o.shim[1], &o.bag})
    if (s->empty())
    {
      std::cerr << "ab_core: --a-core, --a-shim, --b-core, --b-shim and --bag are required\n";
      return false;
    }
  return true;
}

/// Value at quantile q in [0, 1], interpolated between the two nearest ranks; NaN for none.
/// Not bench_stats.hpp's nearest rank: of an even number of ratios that takes the upper of the
/// middle two, and taken twice (over pairs, then over rounds) it put A/A at 1.002 on average
/// (11 runs; 15 runs since: 1.000).
double quantile(std::vector<double> v, double q)
{
  if (v.empty())
    return std::nan("");
  std::sort(v.begin(), v.end());
  const double pos = q * static_cast<double>(v.size() - 1);
  const auto lo = static_cast<std::size_t>(pos);
  const std::size_t hi = std::min(lo + 1, v.size() - 1);
  return v[lo] + (pos - static_cast<double>(lo)) * (v[hi] - v[lo]);
}

double median(const std::vector<double>& v) { return quantile(v, 0.5); }

// Each build's first call with its own variables set (and no other side's), then unset.
bool firstCalls(const Options& opt, ab::Build (&builds)[2], const std::vector<RcAbCloud>& clouds)
{
  for (int i = 0; i < 2 && !clouds.empty(); ++i)
  {
    for (const std::string& e : opt.env[i])
      builds[i].set_env(e.substr(0, e.find('=')).c_str(), e.substr(e.find('=') + 1).c_str(), 1);
    RcAbResult r{};
    const bool ok = ab::run(builds[i], clouds[0], 0, r, nullptr);
    for (const std::string& e : opt.env[i])
      builds[i].unset_env(e.substr(0, e.find('=')).c_str());
    if (!ok)
      return false;
  }
  return true;
}

// What the warm-up pass found: frames whose outputs agree, and A's primitives over all frames.
struct Fingerprints
{
  std::size_t same_frames = 0;
  std::uint64_t primitives = 0;
};

// Untimed warm-up pass (buffers grow to size), which also fingerprints both builds' outputs.
bool warmUp(ab::Build (&builds)[2], const std::vector<RcAbCloud>& clouds, Fingerprints& fp)
{
  for (const RcAbCloud& c : clouds)
  {
    RcAbResult r[2]{};
    for (int i = 0; i < 2; ++i)
      if (!ab::run(builds[i], c, 1, r[i], nullptr))
        return false;
    fp.same_frames += r[0].output_hash == r[1].output_hash && r[0].primitives == r[1].primitives;
    fp.primitives += r[0].primitives;
  }
  return true;
}

// Frame by frame, A then B or B then A: the second call of a pair finds the frame's records
// in cache, so the order flips from one pair to the next (and between rounds, so that each
// frame has each build first equally often even when the bag holds an even number of frames).
bool alternate(const Options& opt, ab::Build (&builds)[2], const std::vector<RcAbCloud>& clouds,
               std::vector<ab::Sample> (&samples)[2])
{
  const std::size_t nf = clouds.size();
  const auto rounds = static_cast<std::size_t>(opt.rounds);
  const std::size_t pairs_per_round = static_cast<std::size_t>(opt.passes) * nf;
  samples[0].reserve(rounds * pairs_per_round);
  samples[1].reserve(rounds * pairs_per_round);
  for (std::size_t r = 0; r < rounds; ++r)
    for (std::size_t k = 0; k < pairs_per_round; ++k)
    {
      const RcAbCloud& c = clouds[k % nf];
      ab::Sample s[2];
      RcAbResult res{};
      const int first = static_cast<int>((k + r) % 2);
      for (int j = 0; j < 2; ++j)
      {
        const int i = j == 0 ? first : 1 - first;
        if (!ab::run(builds[i], c, 0, res, &s[i]))
          return false;
      }
      samples[0].push_back(s[0]);
      samples[1].push_back(s[1]);
    }
  return true;
}

const char* const kRowNames[ab::kRows] = {"grid",       "features", "thresholds",      "classification",
                                          "primitives", "output",   "pipeline (wall)", "pipeline (cpu)"};

// One row of the table: each build's median over all samples, and B/A as the median and 10-90 %
// range over rounds of each round's median of frame-pair ratios.
struct Row
{
  double median[2];
  double ratio[3];
};

Row summarise(const std::vector<ab::Sample> (&samples)[2], int row, std::size_t rounds, std::size_t pairs_per_round)
{
  std::vector<double> v[2], per_round;
  for (int i = 0; i < 2; ++i)
    for (const ab::Sample& s : samples[i])
      v[i].push_back(s[row]);
  for (std::size_t r = 0; r < rounds; ++r)
  {
    std::vector<double> ratios;
    for (std::size_t k = r * pairs_per_round; k < (r + 1) * pairs_per_round; ++k)
      if (samples[0][k][row] > 0)
        ratios.push_back(samples[1][k][row] / samples[0][k][row]);
    if (!ratios.empty())
      per_round.push_back(median(ratios));
  }
  return {{median(v[0]), median(v[1])}, {median(per_round), quantile(per_round, 0.1), quantile(per_round, 0.9)}};
}

void printHeader(const Options& opt, const ab::Build (&builds)[2], std::size_t nf, double mean_points,
                 const Fingerprints& fp)
{
  std::printf("ab_core: %s\n", opt.bag.c_str());
  for (int i = 0; i < 2; ++i)
  {
    std::printf("  %s: %s", builds[i].name, builds[i].core_path.c_str());
    for (const std::string& e : opt.env[i])
      std::printf(" (%s)", e.c_str());
    std::printf("\n");
  }
  std::printf("  %zu frames, %.0f points/frame (mean), %.1f primitives/frame; %zu rounds x %d passes, "
              "A and B alternating frame by frame (+1 warm-up)\n",
              nf, mean_points, static_cast<double>(fp.primitives) / static_cast<double>(nf),
              static_cast<std::size_t>(opt.rounds), opt.passes);
  std::printf("  outputs: %s (%zu of %zu frames with identical fingerprints)\n",
              fp.same_frames == nf ? "same" : "DIFFERENT", fp.same_frames, nf);
}

// The table, one row per stage and two for the whole call, then the machine-readable last line.
void printReport(const Options& opt, const ab::Build (&builds)[2], std::size_t nf, double mean_points,
                 const Fingerprints& fp, const std::vector<ab::Sample> (&samples)[2])
{
  printHeader(opt, builds, nf, mean_points, fp);
  std::printf("  %-16s %9s %9s   %7s %7s %7s   (B/A: median over rounds of each round's median\n", "[ms]",
              "A median", "B median", "B/A", "p10", "p90");
  std::printf("  %-16s %9s %9s   %7s %7s %7s    of frame-pair ratios)\n", "", "", "", "", "", "");
  const auto rounds = static_cast<std::size_t>(opt.rounds);
  const std::size_t pairs_per_round = static_cast<std::size_t>(opt.passes) * nf;
  Row wall{}, cpu{};
  for (int row = 0; row < ab::kRows; ++row)
  {
    const Row r = summarise(samples, row, rounds, pairs_per_round);
    std::printf("  %-16s %9.4f %9.4f   %7.4f %7.4f %7.4f\n", kRowNames[row], r.median[0], r.median[1], r.ratio[0],
                r.ratio[1], r.ratio[2]);
    if (row == ab::kWall)
      wall = r;
    if (row == ab::kCpu)
      cpu = r;
  }
  std::printf("frames=%zu points=%.0f pairs=%zu a_ms=%.4f b_ms=%.4f ratio=%.4f ratio_p10=%.4f ratio_p90=%.4f "
              "cpu_ratio=%.4f cpu_ratio_p10=%.4f cpu_ratio_p90=%.4f outputs=%s\n",
              nf, mean_points, rounds * pairs_per_round, wall.median[0], wall.median[1], wall.ratio[0],
              wall.ratio[1], wall.ratio[2], cpu.ratio[0], cpu.ratio[1], cpu.ratio[2],
              fp.same_frames == nf ? "same" : "DIFFERENT");
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
  ab::Build builds[2];
  builds[0].name = "A";
  builds[1].name = "B";
  for (int i = 0; i < 2; ++i)
    if (!ab::load(opt.core[i], opt.shim[i], builds[i]))
      return 1;

  // Frames are read once, here, and both builds read the very same bytes.
  std::vector<sensor_msgs::PointCloud2::ConstPtr> msgs;
  if (!ab::readFrames(opt.bag, opt.topic, msgs))
    return 1;
  std::vector<RcAbCloud> clouds;
  std::size_t total_points = 0;
  for (const auto& m : msgs)
  {
    clouds.push_back(ab::toCloud(*m));
    total_points += static_cast<std::size_t>(m->width) * m->height;
  }

  Fingerprints fp;
  std::vector<ab::Sample> samples[2];
  if (!firstCalls(opt, builds, clouds) || !warmUp(builds, clouds, fp) || !alternate(opt, builds, clouds, samples))
    return 1;
  for (ab::Build& b : builds)
    b.destroy(b.session);

  const double mean_points = static_cast<double>(total_points) / static_cast<double>(clouds.size());
  printReport(opt, builds, clouds.size(), mean_points, fp, samples);
  return 0;
}
