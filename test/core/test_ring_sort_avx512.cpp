// The ring sort's AVX-512F kernels (ring_sort_avx512.hpp) against their scalar definitions, bit
// for bit. The arrival steps only steer the insertion sort (which seam, which direction), so a
// wrong step or count leaves every grid array the same and no grid test can see it: it is
// checked here. Skipped on CPUs without AVX-512F (and under valgrind, which reports none).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <random>
#include <vector>

#include "../../src/core/ring_sort_avx512.hpp"
#include "ring_curvature/scan_grid.hpp"

using namespace ring_curvature;

#if defined(RC_SIMD_CLONES_ON)
namespace
{
float keyAzimuth(std::uint64_t key)
{
  const auto k = static_cast<std::uint32_t>(key >> 32);
  return detail::bitsFloat((k & 0x80000000u) != 0 ? k ^ 0x80000000u : ~k);
}

// Azimuths of a ring read in firing order: a walk either way with jitter, a wrap across +-pi,
// ties, -0 and +0, and now and then a jump anywhere.
std::vector<float> ringAzimuths(std::mt19937& rng, std::size_t n)
{
  std::uniform_real_distribution<float> u(-3.14159f, 3.14159f), jitter(-0.01f, 0.01f);
  std::vector<float> az(n);
  float a = u(rng);
  const float step = (rng() % 2 == 0 ? 1.0f : -1.0f) * 6.2f / static_cast<float>(n + 1);
  for (std::size_t j = 0; j < n; ++j)
  {
    a += step + jitter(rng);
    if (a > 3.14159f) a -= 6.28318f;
    if (a < -3.14159f) a += 6.28318f;
    const auto pick = static_cast<unsigned>(rng() % 40);
    az[j] = pick == 0 ? -0.0f : pick == 1 ? 0.0f : pick == 2 ? u(rng) : (pick == 3 && j > 0) ? az[j - 1] : a;
  }
  return az;
}
}  // namespace

TEST(RingSortAvx512, SortKeysAreTheScalarKeys)
{
  if (!__builtin_cpu_supports("avx512f")) GTEST_SKIP() << "no AVX-512F";
  std::mt19937 rng(5);
  for (std::size_t n : {0u, 1u, 15u, 16u, 17u, 31u, 32u, 33u, 100u, 512u})
  {
    const std::vector<float> az = ringAzimuths(rng, n);
    // i0 near 2^32: the index wraps as the scalar code's static_cast<std::uint32_t>(i0 + j)
    for (std::size_t i0 : {std::size_t{0}, std::size_t{12345}, std::size_t{0xFFFFFFF8u}})
    {
      std::vector<std::uint64_t> key(n + 1, 0xDEADBEEFDEADBEEFull);
      const std::size_t done = detail::sortKeysAvx512(az.data(), i0, n, key.data());
      EXPECT_EQ(done, n / 16 * 16);
      for (std::size_t j = 0; j < done; ++j)
      {
        const std::uint64_t want = (static_cast<std::uint64_t>(detail::orderedKey(az[j] + 0.0f)) << 32) |
                                   static_cast<std::uint32_t>(i0 + j);
        ASSERT_EQ(key[j], want) << "n " << n << " i0 " << i0 << " j " << j;
      }
      EXPECT_EQ(key[done], 0xDEADBEEFDEADBEEFull) << "wrote past the groups of sixteen";
    }
  }
}

TEST(RingSortAvx512, ArrivalStepsAreTheScalarSteps)
{
  if (!__builtin_cpu_supports("avx512f")) GTEST_SKIP() << "no AVX-512F";
  std::mt19937 rng(9);
  for (std::size_t n : {0u, 1u, 2u, 16u, 17u, 18u, 32u, 33u, 48u, 49u, 200u, 1777u})
  {
    const std::vector<float> az = ringAzimuths(rng, n);
    std::vector<std::uint64_t> src(n);
    for (std::size_t j = 0; j < n; ++j)
      src[j] = (static_cast<std::uint64_t>(detail::orderedKey(az[j] + 0.0f)) << 32) | static_cast<std::uint32_t>(j);
    std::vector<float> step(n + 2, -7.0f);
    std::vector<std::uint8_t> wide(n + 2, 7);
    std::uint32_t down = 0;
    const std::size_t from = detail::arrivalStepsAvx512(src.data(), n, step.data(), wide.data(), down);
    EXPECT_EQ(from, n < 17 ? 1 : 1 + (n - 1) / 16 * 16) << "n " << n;
    std::uint32_t want_down = 0;
    for (std::size_t j = 1; j < from; ++j)
    {
      const float d = keyAzimuth(src[j]) - keyAzimuth(src[j - 1]);
      ASSERT_EQ(std::memcmp(&step[j], &d, sizeof d), 0) << "n " << n << " j " << j;
      ASSERT_EQ(wide[j], ((d < -kPi) | (d > kPi)) ? 1 : 0) << "n " << n << " j " << j;
      want_down += d < 0.0f ? 1u : 0u;
    }
    EXPECT_EQ(down, want_down) << "n " << n;
    EXPECT_EQ(step[from], -7.0f) << "wrote past the steps done";
    EXPECT_EQ(wide[from], 7) << "wrote past the steps done";
  }
}
#endif
