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
struct GatherChoice
{
  bool on;
  const char* reason;
};

GatherChoice chooseGathers()
{
#if defined(RC_SIMD_CLONES_ON)
  if (!__builtin_cpu_supports("avx2")) return {false, "off (no AVX2)"};
  if (const char* env = std::getenv("RC_AVX2_GATHERS"))
  {
    if (std::strcmp(env, "1") == 0) return {true, "on (RC_AVX2_GATHERS=1)"};
    if (std::strcmp(env, "0") == 0) return {false, "off (RC_AVX2_GATHERS=0)"};
    // anything else: as if unset (a typo must not change what a benchmark measures unseen;
    // the banner shows the choice)
  }
  if (__builtin_cpu_is("amd")) return {false, "off (AMD)"};
  return {true, "on"};
#else
  return {false, "off (baseline build)"};
#endif
}

const GatherChoice& choice()
{
  static const GatherChoice c = chooseGathers();  // (thread-safe initialisation)
  return c;
}
}  // namespace

bool avx2Gathers() { return choice().on; }
const char* avx2GathersReason() { return choice().reason; }

}  // namespace detail
}  // namespace ring_curvature
