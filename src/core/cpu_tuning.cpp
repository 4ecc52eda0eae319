#include "cpu_tuning.hpp"
#include "simd_clones.hpp"

#include <cstdlib>
#include <cstring>

namespace ring_curvature
{
namespace detail
{
namespace
{
struct Profile
{
  bool amd;
  const char* name;
};

Profile chooseProfile()
{
  if (const char* env = std::getenv("RC_CPU_TUNING"))
  {
    if (std::strcmp(env, "intel") == 0) return {false, "intel (RC_CPU_TUNING=intel)"};
    if (std::strcmp(env, "amd") == 0) return {true, "amd (RC_CPU_TUNING=amd)"};
    // anything else: as if unset (the banner shows the profile chosen)
  }
#if defined(RC_SIMD_CLONES_ON)
  if (__builtin_cpu_is("amd")) return {true, "amd (AMD CPU)"};
#endif
  return {false, "intel"};
}

const Profile& profile()
{
  static const Profile p = chooseProfile();  // (thread-safe initialisation)
  return p;
}
}  // namespace

bool avx2Gathers()
{
#if defined(RC_SIMD_CLONES_ON)
  static const bool on = __builtin_cpu_supports("avx2") && !profile().amd;
  return on;
#else
  return false;
#endif
}
const char* cpuTuningName() { return profile().name; }

}  // namespace detail
}  // namespace ring_curvature
