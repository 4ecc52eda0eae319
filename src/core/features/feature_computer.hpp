// The feature stage: curvature, smoothness and discontinuity of every grid position, ring by
// ring (Eq 6-11 and the variants of docs/method.md).
#pragma once

#include "ring_curvature/features.hpp"
#include "ring_curvature/params.hpp"
#include "ring_curvature/scan_grid.hpp"

#include <cstdint>
#include <vector>

namespace ring_curvature
{

class FeatureComputer
{
public:
  void compute(const ScanGrid& grid, const Params& params, Features& out);

private:
  /// One ring's features; every position of the ring is written.
  void computeRing(const ScanGrid& grid, const Params& params, int ring, Features& out);
  /// Links free to the left (runs_[0, K)) and right (runs_[K, 2K)) of each sample, capped at
  /// `cap`, and the ring's segments between gaps (seg_); returns the number of segment bounds.
  int ringRuns(const ScanGrid& grid, int ring, int cap);
  /// The ring's azimuths and float ranges with `cap` samples of padding on each side.
  void padRing(const ScanGrid& grid, int ring, int cap);
  void chordCurvature(const ScanGrid& grid, const Params& params, int ring, Features& out);
  void developedCurvature(const ScanGrid& grid, const Params& params, int ring, Features& out);
  void discontinuity(const ScanGrid& grid, const Params& params, int ring, Features& out);

  // scratch for one ring (sized to the largest ring, reused)
  std::vector<float> rho_pad_f_;      // the ring's ranges in float, padded with the seam's neighbours
  std::vector<float> az_pad_;         // and its azimuths
  std::vector<int> runs_;             // links free to the left (first K) and right (next K) of each sample
  std::vector<int> seg_;              // the ring's segments between gaps (their first samples)
  std::vector<float> jump_;           // discontinuity of each link (k - 1, k), and the seam's again
  std::vector<double> prefix_;        // prefix sums for windowed statistics
  std::vector<int> half_;             // chord mode: samples per half chord
  std::vector<float> chord_;          // chord mode: chord products per sample
  std::vector<double> turn_len_;      // other modes: turning angle and arc length per sample
  int cap_ = 0;                       // the padding of rho_pad_f_ and az_pad_ (samples)
};

}  // namespace ring_curvature
