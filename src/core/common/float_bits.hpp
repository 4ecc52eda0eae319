// Floats as their bits: ordered integer keys, branch-free selections, and the fast atan2 the
// grid's azimuths and the features' turning angles share.
#pragma once

#include <cmath>
#include <cstdint>
#include <cstring>

namespace ring_curvature
{

namespace detail
{
inline std::uint32_t floatBits(float f)
{
  std::uint32_t u;
  std::memcpy(&u, &f, sizeof u);
  return u;
}
inline float bitsFloat(std::uint32_t u)
{
  float f;
  std::memcpy(&f, &u, sizeof f);
  return f;
}
/// Float bits mapped to an unsigned key of the same order (negatives reversed, below positives;
/// -0 just below +0): integer comparisons and radix digits of keys order the floats.
inline std::uint32_t orderedKey(float f)
{
  const std::uint32_t u = floatBits(f);
  return u ^ ((0u - (u >> 31)) | 0x80000000u);
}
/// All ones when c, else zero.
inline std::uint32_t maskOf(bool c) { return 0u - static_cast<std::uint32_t>(c); }
/// mask ? a : b, bit for bit, without a branch.
inline float selectBits(std::uint32_t mask, float a, float b)
{
  return bitsFloat((floatBits(a) & mask) | (floatBits(b) & ~mask));
}
}  // namespace detail

/// Fast atan2 (max error ~1e-5 rad) for azimuths and turning angles; exposed for tests. Branch-free
/// so that loops over it vectorize: comparisons on the bit patterns (a float comparison may trap
/// under -ftrapping-math, so the compiler kept branches), selections by masks. Each reproduces the
/// float comparison exactly, NaN included (for |v|: v < w iff bits(v) < bits(w) and w is not NaN;
/// v < 0 iff 0x80000000 < bits(v) <= 0xff800000): max / min as std::max / std::min, and a zero or
/// NaN max gives +0.
inline float fastAtan2(float y, float x)
{
  using detail::floatBits;
  using detail::maskOf;
  using detail::selectBits;
  const float ax = std::fabs(x), ay = std::fabs(y);
  const std::uint32_t bx = floatBits(ax), by = floatBits(ay);
  const std::uint32_t x_lt_y = maskOf(bx < by) & maskOf(by <= 0x7f800000u);  // ax < ay
  const std::uint32_t y_lt_x = maskOf(by < bx) & maskOf(bx <= 0x7f800000u);  // ay < ax
  const float mx = selectBits(x_lt_y, ay, ax), mn = selectBits(y_lt_x, ay, ax);  // std::max, std::min
  const std::uint32_t bm = floatBits(mx);
  const std::uint32_t nonzero = maskOf(bm > 0u) & maskOf(bm <= 0x7f800000u);  // mx > 0
  const float a = mn / selectBits(nonzero, mx, 1.0f);  // the zero / NaN case divides by 1, discarded
  const float s = a * a;
  // Minimax polynomial for atan on [0, 1] (max error ~1e-5 rad, far below a 0.1 deg azimuth step).
  float r = ((((0.0208351f * s - 0.0851330f) * s + 0.1801410f) * s - 0.3302995f) * s + 0.9998660f) * a;
  r = selectBits(x_lt_y, 1.57079637f - r, r);
  const std::uint32_t sx = floatBits(x), sy = floatBits(y);
  r = selectBits(maskOf(sx > 0x80000000u) & maskOf(sx <= 0xff800000u), 3.14159265358979f - r, r);  // x < 0
  r = selectBits(maskOf(sy > 0x80000000u) & maskOf(sy <= 0xff800000u), -r, r);                      // y < 0
  return detail::bitsFloat(floatBits(r) & nonzero);  // +0 where mx is not > 0
}

}  // namespace ring_curvature
