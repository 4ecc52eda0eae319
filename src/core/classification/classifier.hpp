// The classification stage: ring-wise adaptive thresholds (Algorithm 1's quartiles, or the
// robust median + k MAD with noise floors) and the labels they give each grid position.
#pragma once

#include "ring_curvature/classifier.hpp"
#include "ring_curvature/params.hpp"
#include "ring_curvature/scan_grid.hpp"

#include <cstdint>
#include <vector>

namespace ring_curvature
{

class Classifier
{
public:
  /// Computes per-ring thresholds (O(K) selection per ring, no sort; ring_thresholds.cpp).
  void computeThresholds(const ScanGrid& grid, const Features& f, const Params& params,
                         std::vector<RingThresholds>& out);
  /// Labels every grid position (classifier.cpp).
  void classify(const ScanGrid& grid, const Features& f, const Params& params,
                const std::vector<RingThresholds>& thr, std::vector<Label>& labels);

private:
  void suppressNonMaxima(const ScanGrid& grid, const Features& f, std::uint32_t b, std::uint32_t e, bool closed,
                         std::vector<Label>& labels);
  // one ring's scratch (see computeThresholds)
  std::vector<float> scratch_;
};

}  // namespace ring_curvature
