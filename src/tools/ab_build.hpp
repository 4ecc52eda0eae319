// One build of the core as ab_core holds it: its libring_curvature_core.so and shim loaded into
// a link namespace of their own, and one frame's call into it timed.
#pragma once

#include <array>
#include <string>

#include "ab_shim.h"

namespace ring_curvature
{
namespace ab
{

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

/// Loads `core` and then `shim` into a fresh namespace, checks that it holds that core alone and
/// creates a pipeline. False, with the reason on stderr, on any failure.
bool load(const std::string& core, const std::string& shim, Build& b);

// The stages, then the whole call: wall time, and the thread's CPU time.
constexpr int kWall = RC_AB_STAGES, kCpu = RC_AB_STAGES + 1, kRows = RC_AB_STAGES + 2;

/// One build's samples of one frame: the stages' own times, then the call's wall and CPU times.
using Sample = std::array<double, kRows>;

/// Runs the build on one frame (with its output fingerprint if `want_hash`), filling `sample`
/// when given. False, with the build's message on stderr, if it rejects the frame.
bool run(Build& b, const RcAbCloud& cloud, int want_hash, RcAbResult& res, Sample* sample);

}  // namespace ab
}  // namespace ring_curvature
