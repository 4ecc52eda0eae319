// The features' loops over one ring: the chord mode's developed chords and sample counts, and the
// jump mode's link discontinuities, each independent iterations compiled as target clones.
#pragma once

#include <cmath>
#include <limits>

namespace ring_curvature
{
namespace detail
{

// sin / cos of the small angles between ring neighbours (|a| < 0.2 rad almost always): a
// Taylor polynomial is exact to ~1e-12 there and far cheaper than the libm calls.
constexpr double kSmallAngle = 0.2;
template <class T>
inline void polySinCos(T a, T& s, T& c)
{
  // Reciprocal constants: without -ffast-math "/ 6.0" stays a division; differs by an ulp at most.
  const T a2 = a * a;
  s = a * (T(1) - a2 * T(1.0 / 6.0) * (T(1) - a2 * T(1.0 / 20.0) * (T(1) - a2 * T(1.0 / 42.0))));
  c = T(1) - a2 * T(0.5) * (T(1) - a2 * T(1.0 / 12.0) * (T(1) - a2 * T(1.0 / 30.0)));
}
template <class T>
inline void smallSinCos(T a, T& s, T& c)
{
  if (std::fabs(a) > static_cast<T>(kSmallAngle))
  {
    s = std::sin(a);
    c = std::cos(a);
    return;
  }
  polySinCos(a, s, c);
}

// Turning angle and curvature of a sample, NaN where undefined; straight-line (callers pass `&`,
// not `&&`) so that loops vectorize. T is float in chord mode, double in the others.
template <class T>
inline void storeCurvature(T turn, T len, bool defined, float& turning, float& curvature)
{
  const float kappa = static_cast<float>(turn / len);
  turning = defined ? static_cast<float>(turn) : std::numeric_limits<float>::quiet_NaN();
  curvature = (defined & (len > 0)) ? kappa : std::numeric_limits<float>::quiet_NaN();
}

/// Chord mode's developed chords of samples [0, K), vertex k to k - min(H, L) and k + min(H, R), on
/// the padded az, rho: cross, dot, squared lengths. True if an angle exceeded the polynomial's range
/// (then call again with `libm`: the libm sine and cosine where an angle is large).
bool chordProducts(int K, float c, const int* H, const int* L, const int* R, const float* az, const float* rho,
                   float* cross, float* dot, float* v2, float* u2, bool libm);
/// Chord mode: samples per half chord for a chord of `chord` metres at each range, in [1, max_h].
void chordSamples(int K, const float* rho, float cos_phi, float dtheta, float chord, int max_h, int* H);
/// Jump mode: the discontinuity of link (k-1, k) of each sample k from the padded ranges `rp`,
/// NaN where k has no link back.
void linkJumps(int K, const int* L, const int* R, const float* rp, float* jump);
/// Discontinuity of each sample: the larger of its two links' jumps (jump has K + 1 entries).
void largerLink(int K, const int* R, const float* jump, float* disc);

}  // namespace detail
}  // namespace ring_curvature
