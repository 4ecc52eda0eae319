// Ring-wise adaptive thresholds and labels: Algorithm 1 (quartiles) and a robust variant.
#pragma once

#include <vector>

#include "ring_curvature/features.hpp"

namespace ring_curvature
{

/// Thresholds of one ring (low / high for each feature).
struct RingThresholds
{
  float curvature_low = 0, curvature_high = 0;
  float smoothness_high = 0;
  float discontinuity_low = 0, discontinuity_high = 0;
};

class Classifier
{
public:
  /// Computes per-ring thresholds (O(K) selection per ring, no sort).
  void computeThresholds(const ScanGrid& grid, const Features& f, const Params& params,
                         std::vector<RingThresholds>& out);
  /// Labels every grid position.
  void classify(const ScanGrid& grid, const Features& f, const Params& params,
                const std::vector<RingThresholds>& thr, std::vector<Label>& labels);

private:
  void suppressNonMaxima(const ScanGrid& grid, const Features& f, std::uint32_t b, std::uint32_t e, bool closed,
                         std::vector<Label>& labels);
  // one ring's scratch (see computeThresholds)
  std::vector<float> scratch_;
};

/// Value at quantile q of v[0..n) by O(n) selection (v is reordered). NaN when n == 0.
float selectQuantile(float* v, std::size_t n, double q);
/// Value of rank k (0-based, k < n) of v[0..n) by the same selection (v is reordered).
float selectNth(float* v, std::size_t n, std::size_t k);

}  // namespace ring_curvature
