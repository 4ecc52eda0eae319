// One build of the core in a link namespace of its own (dlmopen), and a timed call into it: what
// lets ab_core hold two same-named libraries, and their same-named symbols, apart.
#include "ab_build.hpp"

#include <dlfcn.h>
#include <link.h>

#include <chrono>
#include <climits>
#include <cstdlib>
#include <ctime>
#include <iostream>

namespace ring_curvature
{
namespace ab
{
namespace
{

using Clock = std::chrono::steady_clock;

std::string realPath(const std::string& p)
{
  char buf[PATH_MAX];
  return realpath(p.c_str(), buf) ? std::string(buf) : p;
}

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

double threadCpuMs()
{
  timespec ts{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return static_cast<double>(ts.tv_sec) * 1e3 + static_cast<double>(ts.tv_nsec) * 1e-6;
}

}  // namespace

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

}  // namespace ab
}  // namespace ring_curvature
