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
// src/tools/ab_core.sh builds the shims and runs it. The LAST line is machine-readable:
//   frames=… points=… pairs=… a_ms=… b_ms=… ratio=… ratio_p10=… ratio_p90=…
//   cpu_ratio=… cpu_ratio_p10=… cpu_ratio_p90=… outputs=same|DIFFERENT   (one line)
#include <dlfcn.h>
#include <link.h>
#include <rosbag/bag.h>
#include <rosbag/query.h>
#include <rosbag/view.h>
#include <sensor_msgs/PointCloud2.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <climits>
#include <ctime>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <iostream>
#include <string>
#include <vector>

#include "ab_shim.h"
#include "ring_curvature/params.hpp"  // the default field lists (header-only use: nothing to link)

using Clock = std::chrono::steady_clock;

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

std::string realPath(const std::string& p)
{
  char buf[PATH_MAX];
  return realpath(p.c_str(), buf) ? std::string(buf) : p;
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

/// One build: its namespace, its shim's entry points and its pipeline.
struct Build
{
  const char* name = "";
  std::string core_path;  // the libring_curvature_core.so the namespace really holds
  int (*version)() = nullptr;
  void* (*create)() = nullptr;
  int (*process)(void*, const RcAbCloud*, RcAbResult*, int, char*, size_t) = nullptr;
  void (*destroy)(void*) = nullptr;
  // the namespace's own libc's setenv / unsetenv: each namespace has a libc and an environment
  // of its own, and the main program's setenv does not reach the core's getenv
  int (*set_env)(const char*, const char*, int) = nullptr;
  int (*unset_env)(const char*) = nullptr;
  void* session = nullptr;
};

template <typename F>
bool symbol(void* handle, const char* name, F& out)
{
  void* p = dlsym(handle, name);
  if (!p)
    return false;
  // POSIX guarantees that a data pointer from dlsym can hold a function's address.
  out = reinterpret_cast<F>(p);
  return true;
}

// The core is opened FIRST, by its path, into a fresh namespace; the shim then joins that
// namespace, and its DT_NEEDED libring_curvature_core.so is met by the library already there
// (matched by soname), never looked up on LD_LIBRARY_PATH or RUNPATH, where it could find a
// third build.
bool load(const std::string& core, const std::string& shim, Build& b)
{
  void* hc = dlmopen(LM_ID_NEWLM, core.c_str(), RTLD_NOW | RTLD_LOCAL);
  if (!hc)
  {
    std::cerr << "ab_core: " << b.name << ": " << dlerror() << "\n";
    return false;
  }
  Lmid_t ns = 0;
  if (dlinfo(hc, RTLD_DI_LMID, &ns) != 0)
  {
    std::cerr << "ab_core: " << b.name << ": " << dlerror() << "\n";
    return false;
  }
  void* hs = dlmopen(ns, shim.c_str(), RTLD_NOW | RTLD_LOCAL);
  if (!hs)
  {
    std::cerr << "ab_core: " << b.name << ": " << dlerror() << "\n";
    return false;
  }
  if (!symbol(hs, "rc_ab_version", b.version) || !symbol(hs, "rc_ab_create", b.create) ||
      !symbol(hs, "rc_ab_process", b.process) || !symbol(hs, "rc_ab_destroy", b.destroy) ||
      !symbol(hc, "setenv", b.set_env) || !symbol(hc, "unsetenv", b.unset_env))
  {
    std::cerr << "ab_core: " << b.name << ": " << shim << " lacks the rc_ab_* interface (or no setenv)\n";
    return false;
  }
  if (b.version() != RC_AB_SHIM_VERSION)
  {
    std::cerr << "ab_core: " << b.name << ": shim version " << b.version() << ", expected " << RC_AB_SHIM_VERSION
              << ": rebuild it (src/tools/ab_core.sh does when the build folder holds none)\n";
    return false;
  }
  // Which core library did the namespace end up with? Exactly the one asked for, or the
  // measurement would time something else.
  link_map* lm = nullptr;
  if (dlinfo(hs, RTLD_DI_LINKMAP, &lm) != 0)
    return false;
  while (lm->l_prev)
    lm = lm->l_prev;
  int cores = 0;
  for (; lm; lm = lm->l_next)
    if (std::string(lm->l_name).find("libring_curvature_core") != std::string::npos)
    {
      ++cores;
      b.core_path = realPath(lm->l_name);
    }
  if (cores != 1 || b.core_path != realPath(core))
  {
    std::cerr << "ab_core: " << b.name << ": namespace holds " << cores << " core libraries (" << b.core_path
              << "), expected " << realPath(core) << " alone\n";
    return false;
  }
  b.session = b.create();
  if (!b.session)
  {
    std::cerr << "ab_core: " << b.name << ": cannot create a pipeline\n";
    return false;
  }
  return true;
}

std::uint8_t fieldType(const sensor_msgs::PointCloud2& msg, const char* name, std::int64_t& offset)
{
  for (const auto& f : msg.fields)
    if (f.name == name)
    {
      offset = f.offset;
      return f.datatype;
    }
  offset = -1;
  return 7;  // float32, unused for an absent field
}

// The first field of a comma-separated list that the cloud has, as the adapter picks it.
RcAbField firstField(const sensor_msgs::PointCloud2& msg, const std::string& names)
{
  RcAbField f{};
  f.offset = -1;
  ring_curvature::forEachFieldName(names, [&](std::string_view name) {
    f.type = fieldType(msg, std::string(name).c_str(), f.offset);
    return f.offset >= 0;
  });
  return f;
}

// The field layout as the nodelet's adapter (makeView) finds it with default parameters: x, y, z,
// the first present name of ring_field and of time_field, intensity. The core checks the rest.
RcAbCloud toCloud(const sensor_msgs::PointCloud2& msg)
{
  static const ring_curvature::Params defaults;
  RcAbCloud c{};
  c.data = msg.data.data();
  c.data_size = msg.data.size();
  c.width = msg.width;
  c.height = msg.height;
  c.point_step = msg.point_step;
  c.row_step = msg.row_step;
  c.x.type = fieldType(msg, "x", c.x.offset);
  c.y.type = fieldType(msg, "y", c.y.offset);
  c.z.type = fieldType(msg, "z", c.z.offset);
  c.ring = firstField(msg, defaults.ring_field);
  c.intensity.type = fieldType(msg, "intensity", c.intensity.offset);
  c.time = firstField(msg, defaults.time_field);
  return c;
}

bool readBag(const Options& o, std::vector<sensor_msgs::PointCloud2::ConstPtr>& clouds)
{
  try
  {
    rosbag::Bag bag(o.bag, rosbag::bagmode::Read);
    rosbag::View query;
    if (o.topic.empty())
      query.addQuery(bag, rosbag::TypeQuery("sensor_msgs/PointCloud2"));
    else
      query.addQuery(bag, rosbag::TopicQuery(o.topic));
    for (const rosbag::MessageInstance& m : query)
      if (auto c = m.instantiate<sensor_msgs::PointCloud2>())
        if (!c->is_bigendian)
          clouds.push_back(c);
  }
  catch (const std::exception& e)
  {
    std::cerr << "ab_core: cannot read " << o.bag << ": " << e.what() << "\n";
    return false;
  }
  if (clouds.empty())
    std::cerr << "ab_core: no usable PointCloud2 frames in " << o.bag << "\n";
  return !clouds.empty();
}

// The stages, then the whole call: wall time, and the thread's CPU time.
constexpr int kWall = RC_AB_STAGES, kCpu = RC_AB_STAGES + 1, kRows = RC_AB_STAGES + 2;
const char* const kRowNames[kRows] = {"grid",       "features", "thresholds",      "classification",
                                      "primitives", "output",   "pipeline (wall)", "pipeline (cpu)"};

double threadCpuMs()
{
  timespec ts{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return static_cast<double>(ts.tv_sec) * 1e3 + static_cast<double>(ts.tv_nsec) * 1e-6;
}

/// One build's samples of one frame: the stages' own times, then the call's wall time.
using Sample = std::array<double, kRows>;

bool run(Build& b, const RcAbCloud& cloud, int want_hash, RcAbResult& res, Sample* sample)
{
  char err[512] = "";
  const double c0 = threadCpuMs();
  const auto t0 = Clock::now();
  const int rc = b.process(b.session, &cloud, &res, want_hash, err, sizeof err);
  const double ms = std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
  const double cpu = threadCpuMs() - c0;
  if (rc != 0)
  {
    std::cerr << "ab_core: " << b.name << " rejected a frame: " << err << "\n";
    return false;
  }
  if (sample)
  {
    for (int s = 0; s < RC_AB_STAGES; ++s)
      (*sample)[s] = res.stage_ms[s];
    (*sample)[kWall] = ms;
    (*sample)[kCpu] = cpu;
  }
  return true;
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
  Build builds[2];
  builds[0].name = "A";
  builds[1].name = "B";
  for (int i = 0; i < 2; ++i)
    if (!load(opt.core[i], opt.shim[i], builds[i]))
      return 1;

  // Frames are read once, here, and both builds read the very same bytes.
  std::vector<sensor_msgs::PointCloud2::ConstPtr> msgs;
  if (!readBag(opt, msgs))
    return 1;
  std::vector<RcAbCloud> clouds;
  std::size_t total_points = 0;
  for (const auto& m : msgs)
  {
    clouds.push_back(toCloud(*m));
    total_points += static_cast<std::size_t>(m->width) * m->height;
  }
  const std::size_t nf = clouds.size();

  // Each build's first call with its own variables set (and no other side's), then unset.
  for (int i = 0; i < 2 && nf > 0; ++i)
  {
    for (const std::string& e : opt.env[i])
      builds[i].set_env(e.substr(0, e.find('=')).c_str(), e.substr(e.find('=') + 1).c_str(), 1);
    RcAbResult r{};
    const bool ok = run(builds[i], clouds[0], 0, r, nullptr);
    for (const std::string& e : opt.env[i])
      builds[i].unset_env(e.substr(0, e.find('=')).c_str());
    if (!ok)
      return 1;
  }

  // Untimed warm-up pass (buffers grow to size), which also fingerprints both builds' outputs.
  std::size_t same_frames = 0;
  std::uint64_t primitives = 0;
  for (const RcAbCloud& c : clouds)
  {
    RcAbResult r[2]{};
    for (int i = 0; i < 2; ++i)
      if (!run(builds[i], c, 1, r[i], nullptr))
        return 1;
    same_frames += r[0].output_hash == r[1].output_hash && r[0].primitives == r[1].primitives;
    primitives += r[0].primitives;
  }

  // Frame by frame, A then B or B then A: the second call of a pair finds the frame's records
  // in cache, so the order flips from one pair to the next (and between rounds, so that each
  // frame has each build first equally often even when the bag holds an even number of frames).
  const auto rounds = static_cast<std::size_t>(opt.rounds);
  const std::size_t pairs_per_round = static_cast<std::size_t>(opt.passes) * nf;
  std::vector<Sample> samples[2];
  samples[0].reserve(rounds * pairs_per_round);
  samples[1].reserve(rounds * pairs_per_round);
  for (std::size_t r = 0; r < rounds; ++r)
    for (std::size_t k = 0; k < pairs_per_round; ++k)
    {
      const RcAbCloud& c = clouds[k % nf];
      Sample s[2];
      RcAbResult res{};
      const int first = static_cast<int>((k + r) % 2);
      for (int j = 0; j < 2; ++j)
      {
        const int i = j == 0 ? first : 1 - first;
        if (!run(builds[i], c, 0, res, &s[i]))
          return 1;
      }
      samples[0].push_back(s[0]);
      samples[1].push_back(s[1]);
    }
  for (Build& b : builds)
    b.destroy(b.session);

  // Per row: each build's median over all samples; the ratio of every pair, each round's median
  // of them, and the median and 10-90 % range of those round ratios.
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
              nf, static_cast<double>(total_points) / static_cast<double>(nf),
              static_cast<double>(primitives) / static_cast<double>(nf), rounds, opt.passes);
  std::printf("  outputs: %s (%zu of %zu frames with identical fingerprints)\n",
              same_frames == nf ? "same" : "DIFFERENT", same_frames, nf);
  std::printf("  %-16s %9s %9s   %7s %7s %7s   (B/A: median over rounds of each round's median\n", "[ms]",
              "A median", "B median", "B/A", "p10", "p90");
  std::printf("  %-16s %9s %9s   %7s %7s %7s    of frame-pair ratios)\n", "", "", "", "", "", "");
  double round_ratio[3] = {0, 0, 0}, cpu_ratio[3] = {0, 0, 0}, wall_ms[2] = {0, 0};
  for (int row = 0; row < kRows; ++row)
  {
    std::vector<double> v[2], per_round;
    for (int i = 0; i < 2; ++i)
      for (const Sample& s : samples[i])
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
    const double q[3] = {median(per_round), quantile(per_round, 0.1), quantile(per_round, 0.9)};
    std::printf("  %-16s %9.4f %9.4f   %7.4f %7.4f %7.4f\n", kRowNames[row], median(v[0]),
                median(v[1]), q[0], q[1], q[2]);
    if (row == kWall)
    {
      std::copy(q, q + 3, round_ratio);
      wall_ms[0] = median(v[0]);
      wall_ms[1] = median(v[1]);
    }
    if (row == kCpu)
      std::copy(q, q + 3, cpu_ratio);
  }
  std::printf("frames=%zu points=%.0f pairs=%zu a_ms=%.4f b_ms=%.4f ratio=%.4f ratio_p10=%.4f ratio_p90=%.4f "
              "cpu_ratio=%.4f cpu_ratio_p10=%.4f cpu_ratio_p90=%.4f outputs=%s\n",
              nf, static_cast<double>(total_points) / static_cast<double>(nf), rounds * pairs_per_round,
              wall_ms[0], wall_ms[1], round_ratio[0], round_ratio[1], round_ratio[2],
              cpu_ratio[0], cpu_ratio[1], cpu_ratio[2], same_frames == nf ? "same" : "DIFFERENT");
  return 0;
}
