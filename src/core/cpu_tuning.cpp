#include "cpu_tuning.hpp"
#include "simd_clones.hpp"

#include <cstdlib>
#include <cstring>
#include <string>

namespace ring_curvature
{
namespace detail
{
namespace
{
struct Profile
{
  bool amd;
  std::string name;
};

Profile chooseProfile()
{
  std::string ignored;
  const char* const env = std::getenv("RC_CPU_TUNING");
  if (env != nullptr && *env != 0)  // (set but empty: as unset)
  {
    if (std::strcmp(env, "intel") == 0) return {false, "intel (RC_CPU_TUNING=intel)"};
    if (std::strcmp(env, "amd") == 0) return {true, "amd (RC_CPU_TUNING=amd)"};
    // anything else is named in the banner and otherwise ignored: a typo must not pass unseen,
    // nor stop a library that has no channel for errors at load time
    ignored = std::string("; RC_CPU_TUNING='") + env + "' ignored: not intel or amd";
  }
#if defined(RC_SIMD_CLONES_ON)
  if (__builtin_cpu_is("amd")) return {true, "amd (AMD CPU" + ignored + ")"};
#endif
  return {false, ignored.empty() ? std::string("intel") : "intel (" + ignored.substr(2) + ")"};
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
const char* cpuTuningName() { return profile().name.c_str(); }

namespace
{
struct Avx512Cap
{
  bool off;
  std::string note;
};

Avx512Cap chooseAvx512Cap()
{
  const char* const env = std::getenv("RC_CPU_AVX512");
  if (env == nullptr || *env == 0 || std::strcmp(env, "on") == 0) return {false, ""};
  if (std::strcmp(env, "off") == 0) return {true, "; AVX-512 forms off (RC_CPU_AVX512=off)"};
  // (named in the banner, as RC_CPU_TUNING's typos are)
  return {false, std::string("; RC_CPU_AVX512='") + env + "' ignored: not off or on"};
}

const Avx512Cap& avx512Cap()
{
  static const Avx512Cap c = chooseAvx512Cap();
  return c;
}
}  // namespace

bool avx512Forms()
{
#if defined(RC_SIMD_CLONES_ON)
  static const bool on = __builtin_cpu_supports("avx512f") && !avx512Cap().off;
  return on;
#else
  return false;
#endif
}
const char* avx512Note() { return avx512Cap().note.c_str(); }

}  // namespace detail
}  // namespace ring_curvature
