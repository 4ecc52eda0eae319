// Shared by the LOAM tests (test_loam_selector*.cpp, test_loam_degeneracy.cpp): a VLP-16-like
// sensor, ray-cast scenes, a pipeline run with its LOAM sets, and the checks every set must pass.
#pragma once

#include <gtest/gtest.h>
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <map>
#include <random>
#include <set>
#include <string>
#include <tuple>
#include <vector>
#include "loam/degeneracy.hpp"
#include "ring_curvature/pipeline.hpp"

#include "ray_scene.hpp"

namespace ring_curvature
{
namespace test
{

inline constexpr double kPi = 3.14159265358979323846;
inline constexpr double kDeg = kPi / 180;

inline SensorModel vlp16() { return SensorModel::uniform(16, -15, 15, 0.2); }

inline Params baseParams()
{
  Params p;
  p.range_noise = 0.003f;  // a noise-free scan: the sensor's noise is ~0
  return p;
}

// The box scene of test_box_scene.cpp: creases, depth jumps and faces seen at an angle.
inline RayScene boxScene()
{
  RayScene s;
  s.boxes.push_back({9.0, 2.0, -1.8, 2.5, 2.0, 1.5, 30 * kDeg});
  s.boxes.push_back({-7.0, -6.0, -1.8, 0.0, 2.2, 1.0, -20 * kDeg});
  s.boxes.push_back({14.0, 6.0, -1.8, 4.0, 1.5, 3.0, 10 * kDeg});
  s.boxes.push_back({2.0, -12.0, -1.8, 3.0, 4.0, 1.0, 0.0});
  return s;
}

/// A scanned frame run through the pipeline, and its LOAM sets.
struct LoamRun
{
  ScannedFrame f;
  Pipeline pipe;
  LoamFeatures loam;
  LoamRun(const RayScene& scene, const Params& params, double noise = 0.0, double start = 0.0)
      : f(scan(scene, vlp16(), noise, 3, start)), pipe(params)
  {
    FrameResult r;
    EXPECT_TRUE(pipe.process(f.cloud.view(), r).ok);
    pipe.selectLoamFeatures(f.cloud.view(), loam);
  }
  /// The same frame's sets under other LOAM parameters (labels do not depend on them).
  LoamFeatures reselect(const Params& params)
  {
    EXPECT_TRUE(pipe.setParams(params).ok);
    LoamFeatures out;
    pipe.selectLoamFeatures(f.cloud.view(), out);
    return out;
  }
  const ScanGrid& grid() const { return pipe.grid(); }
  const Hit& hit(std::uint32_t p) const { return f.hits[grid().index[p]]; }
};

inline bool isSharpLabel(Label l) { return l == Label::Edge || l == Label::Corner; }

/// Sector of local index k on a ring of K positions (the selector's equal index parts).
inline int sectorOf(std::uint32_t k, std::uint32_t K, int sectors)
{
  for (int s = 0; s < sectors; ++s)
  {
    const std::uint64_t hi = static_cast<std::uint64_t>(K) * static_cast<std::uint64_t>(s + 1) / static_cast<std::uint64_t>(sectors);
    if (k < hi) return s;
  }
  return sectors - 1;
}

struct MaxCounts
{
  int sharp = 0, less_sharp = 0, flat = 0;
};

/// Everything the sets must satisfy whatever the scene: quotas, inclusions, order, labels.
inline MaxCounts checkSets(const Pipeline& pipe, const LoamFeatures& L, const Params& P)
{
  const ScanGrid& g = pipe.grid();
  const std::vector<Label>& labels = pipe.gridLabels();
  const std::vector<float>& jump = pipe.features().discontinuity;
  EXPECT_EQ(L.sweep_time.size(), g.size());
  // Less sharp: the Edge/Corner picks (under the quotas below) and every Rough point at a depth
  // jump (above loam_rough_jump, whatever the quotas).
  const auto outline = [&](std::uint32_t p) {
    return P.loam_rough_jump > 0.0f && labels[p] == Label::Rough && jump[p] > P.loam_rough_jump;
  };
  std::vector<std::uint32_t> picked;
  std::size_t outlines = 0;
  for (const std::uint32_t p : L.less_sharp)
    if (p < g.size() && labels[p] == Label::Rough)
      ++outlines;
    else
      picked.push_back(p);
  std::size_t want_outlines = 0;
  for (std::uint32_t p = 0; p < g.size(); ++p) want_outlines += outline(p);
  EXPECT_EQ(outlines, want_outlines) << "less sharp holds not every Rough point at a jump";
  const std::vector<const std::vector<std::uint32_t>*> sets = {&L.sharp, &L.less_sharp, &L.flat, &L.less_flat};
  const char* names[] = {"sharp", "less_sharp", "flat", "less_flat"};
  for (std::size_t i = 0; i < sets.size(); ++i)
  {
    const auto& v = *sets[i];
    std::set<std::uint32_t> seen;
    int last_ring = -1;
    for (const std::uint32_t p : v)
    {
      if (p >= g.size())
      {
        ADD_FAILURE() << names[i] << ": position " << p << " beyond the grid";
        continue;
      }
      EXPECT_TRUE(seen.insert(p).second) << names[i] << ": position " << p << " twice";
      const int n = g.ringOf(p);
      EXPECT_GE(n, last_ring) << names[i] << " not in ring order at position " << p;
      last_ring = n;
      const Label l = labels[p];
      if (i == 1 && l == Label::Rough)
      {
        EXPECT_TRUE(outline(p)) << "less sharp Rough point " << p << " with discontinuity " << jump[p];
        continue;
      }
      EXPECT_NE(l, Label::Rough) << names[i];
      if (i < 2)
        EXPECT_TRUE(isSharpLabel(l)) << names[i] << " point " << p << " labelled " << labelName(l);
      else
        EXPECT_EQ(l, Label::Plane) << names[i] << " point " << p << " labelled " << labelName(l);
    }
  }
  const std::set<std::uint32_t> less_sharp(L.less_sharp.begin(), L.less_sharp.end()),
      less_flat(L.less_flat.begin(), L.less_flat.end());
  for (const std::uint32_t p : L.sharp) EXPECT_TRUE(less_sharp.count(p)) << "sharp " << p << " not less sharp";
  for (const std::uint32_t p : L.flat) EXPECT_TRUE(less_flat.count(p)) << "flat " << p << " not less flat";

  // Per ring and sector: counts within the quotas, and the sharp points are the first (best)
  // picks of the less sharp ones there.
  using Key = std::pair<int, int>;
  std::map<Key, std::vector<std::uint32_t>> sharp, less, flat;
  const auto bin = [&](const std::vector<std::uint32_t>& v, std::map<Key, std::vector<std::uint32_t>>& m) {
    for (const std::uint32_t p : v)
    {
      const int n = g.ringOf(p);
      const std::uint32_t b = g.ring_begin[static_cast<std::size_t>(n)];
      m[{n, sectorOf(p - b, g.ringSize(n), P.loam_sectors)}].push_back(p);
    }
  };
  bin(L.sharp, sharp);
  bin(picked, less);
  bin(L.flat, flat);
  MaxCounts mc;
  for (const auto& e : sharp)
  {
    EXPECT_LE(static_cast<int>(e.second.size()), P.loam_sharp_per_sector) << "ring " << e.first.first << " sector " << e.first.second;
    mc.sharp = std::max(mc.sharp, static_cast<int>(e.second.size()));
  }
  for (const auto& e : less)
  {
    EXPECT_LE(static_cast<int>(e.second.size()), P.loam_less_sharp_per_sector) << "ring " << e.first.first << " sector " << e.first.second;
    mc.less_sharp = std::max(mc.less_sharp, static_cast<int>(e.second.size()));
    const std::size_t want = std::min(e.second.size(), static_cast<std::size_t>(P.loam_sharp_per_sector));
    const auto it = sharp.find(e.first);
    const std::vector<std::uint32_t> got = it == sharp.end() ? std::vector<std::uint32_t>{} : it->second;
    EXPECT_EQ(got, std::vector<std::uint32_t>(e.second.begin(), e.second.begin() + static_cast<std::ptrdiff_t>(want)))
        << "ring " << e.first.first << " sector " << e.first.second << ": sharp are not the first less sharp picks";
  }
  for (const auto& e : flat)
  {
    EXPECT_LE(static_cast<int>(e.second.size()), P.loam_flat_per_sector) << "ring " << e.first.first << " sector " << e.first.second;
    mc.flat = std::max(mc.flat, static_cast<int>(e.second.size()));
  }
  return mc;
}

/// Linked ring walk (independent of the core's RingLinks): the position `steps` linked samples
/// after (dir = +1) or before (dir = -1) p, or -1 across a gap or an open end.
inline std::int64_t walk(const ScanGrid& g, std::uint32_t p, int dir, int steps)
{
  const int n = g.ringOf(p);
  const std::uint32_t b = g.ring_begin[static_cast<std::size_t>(n)], K = g.ringSize(n);
  const bool closed = g.ring_closed[static_cast<std::size_t>(n)] != 0;
  std::uint32_t k = p - b;
  for (int i = 0; i < steps; ++i)
  {
    if (dir > 0)
    {
      if (k + 1 == K && !closed) return -1;
      const std::uint32_t q = (k + 1) % K;
      if (!g.linked[b + q]) return -1;
      k = q;
    }
    else
    {
      if (k == 0 && !closed) return -1;
      if (!g.linked[b + k]) return -1;
      k = (k + K - 1) % K;
    }
  }
  return static_cast<std::int64_t>(b + k);
}

inline std::set<std::uint32_t> allSets(const LoamFeatures& L)
{
  std::set<std::uint32_t> s(L.sharp.begin(), L.sharp.end());
  s.insert(L.less_sharp.begin(), L.less_sharp.end());
  s.insert(L.flat.begin(), L.flat.end());
  s.insert(L.less_flat.begin(), L.less_flat.end());
  return s;
}

}  // namespace test
}  // namespace ring_curvature
