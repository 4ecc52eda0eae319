// Issue 30 (item 3): the degeneracy report (loam/degeneracy.cpp) on ray-cast scenes whose answer
// is known: the information matrix of a corridor, a tunnel, an open street and a room.
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
#include "../support/loam_run.hpp"

using namespace ring_curvature;
using namespace ring_curvature::test;

namespace
{

// --- 6. degeneracy ----------------------------------------------------------------------------

void printReport(const char* scene, const DegeneracyReport& r)
{
  std::printf("degeneracy %-22s planes %5u lines %4u eigenvalues %.3g %.3g %.3g %.3g %.3g %.3g weakest "
              "[%.2f %.2f %.2f | %.2f %.2f %.2f] %s\n",
              scene, r.plane_constraints, r.line_constraints, r.eigenvalues[0], r.eigenvalues[1], r.eigenvalues[2],
              r.eigenvalues[3], r.eigenvalues[4], r.eigenvalues[5], r.weakest_direction[0], r.weakest_direction[1],
              r.weakest_direction[2], r.weakest_direction[3], r.weakest_direction[4], r.weakest_direction[5],
              r.degenerate ? "DEGENERATE" : "ok");
}

RayScene corridor()
{
  RayScene s;
  s.boxes.push_back({0.0, 2.1, -1.8, 1.2, 100.0, 0.1, 0.0});   // walls at y = +-2, 3 m high, 200 m long
  s.boxes.push_back({0.0, -2.1, -1.8, 1.2, 100.0, 0.1, 0.0});
  return s;
}

RayScene tunnel()
{
  RayScene s = corridor();
  s.boxes.push_back({0.0, 0.0, 1.2, 1.5, 100.0, 2.2, 0.0});  // the ceiling
  return s;
}

RayScene street()
{
  RayScene s;
  for (int i = -3; i <= 3; ++i)  // blocks 16 m long with 6 m gaps, 7.5 m from the axis, 12 m high
  {
    s.boxes.push_back({22.0 * i, 10.0, -1.8, 10.0, 8.0, 2.5, 0.0});
    s.boxes.push_back({22.0 * i + 11.0, -10.0, -1.8, 10.0, 8.0, 2.5, 0.0});
  }
  // poles and a sign
  s.boxes.push_back({5.0, 5.5, -1.8, 3.0, 0.15, 0.15, 0.0});
  s.boxes.push_back({-12.0, -5.5, -1.8, 3.0, 0.15, 0.15, 0.0});
  s.boxes.push_back({18.0, -5.5, -1.8, 3.0, 0.15, 0.15, 0.0});
  s.boxes.push_back({-25.0, 5.5, -1.8, 3.0, 0.15, 0.15, 0.0});
  s.boxes.push_back({10.0, -4.5, -1.8, 2.0, 1.0, 0.1, 30 * kDeg});
  return s;
}

/// A scene's report, printed with its parts (planes only, lines only) and, for comparison, the
/// report of the same less flat points with the ray caster's true normals.
DegeneracyReport sceneReport(const char* name, const RayScene& scene, double noise = 0.0,
                             DegeneracyReport* true_normals = nullptr)
{
  Params P = baseParams();
  if (noise > 0) P.range_noise = static_cast<float>(noise);
  LoamRun run(scene, P, noise);
  checkSets(run.pipe, run.loam, P);
  char label[96];
  std::snprintf(label, sizeof label, "%s", name);
  printReport(label, run.loam.degeneracy);
  LoamFeatures planes = run.loam, lines = run.loam;
  planes.less_sharp.clear();
  lines.less_flat.clear();
  std::snprintf(label, sizeof label, "  %s, planes only", name);
  printReport(label, assessDegeneracy(run.grid(), run.pipe.gridLabels(), planes, P));
  std::snprintf(label, sizeof label, "  %s, lines only", name);
  printReport(label, assessDegeneracy(run.grid(), run.pipe.gridLabels(), lines, P));
  InformationMatrix info(static_cast<double>(P.degeneracy_length));
  for (const std::uint32_t p : run.loam.less_flat)
  {
    const Hit& h = run.hit(p);
    double n[3] = {0, 0, 0};
    n[h.object == 0 ? 2 : h.face / 2] = 1;  // ground: z; box faces 0-5: -x +x -y +y bottom top (axis-aligned boxes)
    const double q[3] = {run.grid().x[p], run.grid().y[p], run.grid().z[p]};
    info.addPlane(q, n);
  }
  const DegeneracyReport truth = info.report(static_cast<double>(P.degeneracy_min_eigenvalue));
  std::snprintf(label, sizeof label, "  %s, true normals", name);
  printReport(label, truth);
  if (true_normals) *true_normals = truth;
  return run.loam.degeneracy;
}

void expectAscendingUnit(const DegeneracyReport& r)
{
  for (int i = 1; i < 6; ++i) EXPECT_LE(r.eigenvalues[static_cast<std::size_t>(i - 1)], r.eigenvalues[static_cast<std::size_t>(i)]);
  double n = 0;
  for (const double c : r.weakest_direction) n += c * c;
  EXPECT_NEAR(n, 1.0, 1e-9);
}

TEST(LoamDegeneracy, CorridorAndTunnelAreDegenerate)
{
  for (const double noise : {0.0, 0.01})
  {
    const DegeneracyReport c = sceneReport(noise > 0 ? "corridor, 1 cm noise" : "corridor", corridor(), noise);
    const DegeneracyReport t = sceneReport(noise > 0 ? "tunnel, 1 cm noise" : "tunnel", tunnel(), noise);
    for (const DegeneracyReport* r : {&c, &t})
    {
      expectAscendingUnit(*r);
      EXPECT_GT(r->plane_constraints, 100u);
      EXPECT_TRUE(r->degenerate) << "noise " << noise;
    }
  }
}

// The scenes themselves are right: with exact normals, a corridor and a tunnel leave exactly the
// translation along x unconstrained.
TEST(LoamDegeneracy, CorridorAndTunnelWithTrueNormalsLeaveTranslationX)
{
  for (const bool with_ceiling : {false, true})
  {
    DegeneracyReport truth;
    sceneReport(with_ceiling ? "tunnel" : "corridor", with_ceiling ? tunnel() : corridor(), 0.0, &truth);
    EXPECT_NEAR(truth.eigenvalues[0], 0.0, 1e-9);
    EXPECT_GT(std::fabs(truth.weakest_direction[3]), 0.99);
    EXPECT_TRUE(truth.degenerate);
  }
}

// The weakest direction of a corridor and a tunnel is translation along the axis, with 1 cm range
// noise too: roll about the axis is weak as well between walls 4 m apart (measured at
// degeneracy_length 10 m), and normals tilted by noise would make the two tie.
TEST(LoamDegeneracy, CorridorAndTunnelWeakestIsTranslationAlongTheAxis)
{
  int wrong = 0;
  std::string what;
  for (const double noise : {0.0, 0.01})
    for (const bool with_ceiling : {false, true})
    {
      const DegeneracyReport r = sceneReport(with_ceiling ? "tunnel" : "corridor", with_ceiling ? tunnel() : corridor(), noise);
      EXPECT_TRUE(r.degenerate);
      if (noise == 0.0)
      {
        EXPECT_GT(std::fabs(r.weakest_direction[3]), 0.9) << (with_ceiling ? "tunnel" : "corridor");
      }
      if (!(std::fabs(r.weakest_direction[3]) > 0.9))
      {
        ++wrong;
        char line[200];
        std::snprintf(line, sizeof line, " %s (noise %.2f): |weakest[3]| %.3f, weakest [%.2f %.2f %.2f | %.2f %.2f %.2f];",
                      with_ceiling ? "tunnel" : "corridor", noise, std::fabs(r.weakest_direction[3]),
                      r.weakest_direction[0], r.weakest_direction[1], r.weakest_direction[2], r.weakest_direction[3],
                      r.weakest_direction[4], r.weakest_direction[5]);
        what += line;
      }
    }
  EXPECT_EQ(wrong, 0) << "the weakest direction is not translation x:" << what;
}

/// A corridor of walls 9.8 m high, `half_width` from its axis: the roll about the axis is well
/// constrained there, so translation x alone is left.
RayScene wideCorridor(double half_width)
{
  RayScene s;
  s.boxes.push_back({0.0, half_width + 0.1, -1.8, 8.0, 100.0, 0.1, 0.0});
  s.boxes.push_back({0.0, -half_width - 0.1, -1.8, 8.0, 100.0, 0.1, 0.0});
  return s;
}

TEST(LoamDegeneracy, WideCorridorIsDegenerateAlongItsAxis)
{
  for (const double w : {4.0, 6.0, 8.0})
  {
    char name[64];
    std::snprintf(name, sizeof name, "corridor +-%.0f m", w);
    const DegeneracyReport r = sceneReport(name, wideCorridor(w));
    expectAscendingUnit(r);
    EXPECT_TRUE(r.degenerate) << name;
    EXPECT_GT(std::fabs(r.weakest_direction[3]), 0.9) << name;
  }
}

// With 1 cm range noise: the noise tilts each plane's normal, and every tilt adds a little of
// every direction's information; the chords along the ring are long enough to keep that below
// the threshold.
TEST(LoamDegeneracy, WideCorridorWithRangeNoiseIsDegenerate)
{
  for (const double w : {4.0, 6.0, 8.0})
  {
    char name[64];
    std::snprintf(name, sizeof name, "corridor +-%.0f m, 1 cm noise", w);
    const DegeneracyReport r = sceneReport(name, wideCorridor(w), 0.01);
    expectAscendingUnit(r);
    EXPECT_TRUE(r.degenerate) << name;
    EXPECT_GT(std::fabs(r.weakest_direction[3]), 0.9) << name;
  }
}

TEST(LoamDegeneracy, OpenStreetIsNotDegenerate)
{
  for (const double noise : {0.0, 0.01})
  {
    const DegeneracyReport r = sceneReport(noise > 0 ? "street, 1 cm noise" : "street", street(), noise);
    expectAscendingUnit(r);
    EXPECT_GT(r.line_constraints, 0u);
    EXPECT_FALSE(r.degenerate) << "noise " << noise;
  }
}

// The room's weakest eigenvalue (pitch) is about 0.0099 without noise: the default threshold sits
// between it and the noisy corridor's 0.0052.
TEST(LoamDegeneracy, SquareRoomIsNotDegenerate)
{
  std::string what;
  for (const double noise : {0.0, 0.01})
  {
    const DegeneracyReport r = sceneReport(noise > 0 ? "room, 1 cm noise" : "room", squareRoom(-1.8), noise);
    expectAscendingUnit(r);
    if (r.degenerate)
    {
      char line[120];
      std::snprintf(line, sizeof line, " noise %.2f: smallest eigenvalue %.5f;", noise, r.eigenvalues[0]);
      what += line;
    }
  }
  EXPECT_TRUE(what.empty()) << "the room is reported degenerate:" << what;
}

TEST(InformationMatrix, PlanesOfThreeNormalsGiveFullRank)
{
  InformationMatrix info(10.0);
  for (int i = -2; i <= 2; ++i)
    for (int j = -2; j <= 2; ++j)
    {
      const double a = 2.0 * i, b = 1.5 * j;
      const double px[3] = {6.0, a, b}, nx[3] = {-1, 0, 0};
      const double py[3] = {a, -5.0, b}, ny[3] = {0, 1, 0};
      const double pz[3] = {a, b, -1.8}, nz[3] = {0, 0, 1};
      info.addPlane(px, nx);
      info.addPlane(py, ny);
      info.addPlane(pz, nz);
    }
  const DegeneracyReport r = info.report(0.01);
  printReport("planes x, y, z", r);
  expectAscendingUnit(r);
  EXPECT_EQ(r.plane_constraints, 75u);
  EXPECT_EQ(r.line_constraints, 0u);
  EXPECT_GT(r.eigenvalues[0], 0.01);
  EXPECT_FALSE(r.degenerate);
}

TEST(InformationMatrix, PlanesWithoutAnXNormalLeaveTranslationX)
{
  InformationMatrix info(10.0);
  for (int i = -3; i <= 3; ++i)
    for (int j = -2; j <= 2; ++j)
    {
      const double a = 3.0 * i, b = 0.7 * j;
      const double py1[3] = {a, 2.0, b}, ny1[3] = {0, -1, 0};
      const double py2[3] = {a, -2.0, b}, ny2[3] = {0, 1, 0};
      const double pz[3] = {a, 0.8 * j, -1.8}, nz[3] = {0, 0, 1};
      info.addPlane(py1, ny1);
      info.addPlane(py2, ny2);
      info.addPlane(pz, nz);
    }
  const DegeneracyReport r = info.report(0.01);
  printReport("planes y, z", r);
  expectAscendingUnit(r);
  EXPECT_NEAR(r.eigenvalues[0], 0.0, 1e-12);
  EXPECT_GT(r.eigenvalues[1], 1e-3);
  EXPECT_NEAR(std::fabs(r.weakest_direction[3]), 1.0, 1e-9);
  EXPECT_TRUE(r.degenerate);
}

TEST(InformationMatrix, LineAddsTwoRowsAcrossIt)
{
  // One plane row (translation x) and one line along z at the origin (translation x and y):
  // H / rows has translation x 2/3 and y 1/3 with three rows (1 and 1/2 if the line were one).
  InformationMatrix info(10.0);
  const double o[3] = {0, 0, 0}, nx[3] = {1, 0, 0}, dz[3] = {0, 0, 1};
  info.addPlane(o, nx);
  info.addLine(o, dz);
  const DegeneracyReport r = info.report(0.01);
  printReport("plane + line", r);
  EXPECT_EQ(r.plane_constraints, 1u);
  EXPECT_EQ(r.line_constraints, 1u);
  EXPECT_NEAR(r.eigenvalues[5], 2.0 / 3.0, 1e-12);
  EXPECT_NEAR(r.eigenvalues[4], 1.0 / 3.0, 1e-12);
  EXPECT_NEAR(r.eigenvalues[3], 0.0, 1e-12);
  EXPECT_TRUE(r.degenerate);  // 3 rows cannot pin 6 unknowns

  // Lines of one direction d at scattered points: all but translation along d is pinned.
  InformationMatrix lines(10.0);
  const double s3 = 1.0 / std::sqrt(3.0);
  const double d[3] = {s3, s3, s3};
  const double pts[6][3] = {{5, 0, 0}, {0, 5, 1}, {-3, -4, 2}, {2, -6, -1}, {-7, 3, 0.5}, {1, 1, -5}};
  for (const auto& p : pts) lines.addLine(p, d);
  const DegeneracyReport l = lines.report(0.01);
  printReport("lines along (1,1,1)", l);
  expectAscendingUnit(l);
  EXPECT_EQ(l.line_constraints, 6u);
  EXPECT_NEAR(l.eigenvalues[0], 0.0, 1e-12);
  EXPECT_GT(l.eigenvalues[1], 1e-3);
  const double along = l.weakest_direction[3] * d[0] + l.weakest_direction[4] * d[1] + l.weakest_direction[5] * d[2];
  EXPECT_NEAR(std::fabs(along), 1.0, 1e-9);
}

TEST(InformationMatrix, RotationCountsAtTheLength)
{
  // A plane of normal x at (0, L, 0): J = (0, 0, -1, 1, 0, 0) with rotation in metres at L.
  InformationMatrix info(10.0);
  const double p[3] = {0, 10, 0}, n[3] = {1, 0, 0};
  info.addPlane(p, n);
  const DegeneracyReport r = info.report(0.01);
  EXPECT_NEAR(r.eigenvalues[5], 2.0, 1e-12);
  EXPECT_NEAR(r.eigenvalues[4], 0.0, 1e-12);
}

TEST(InformationMatrix, NoRowsIsDegenerate)
{
  const InformationMatrix info(10.0);
  const DegeneracyReport r = info.report(0.01);
  EXPECT_EQ(r.plane_constraints, 0u);
  EXPECT_EQ(r.line_constraints, 0u);
  for (const double e : r.eigenvalues) EXPECT_EQ(e, 0.0);
  EXPECT_TRUE(r.degenerate);
  // and with a threshold of 0, which no eigenvalue is below
  EXPECT_TRUE(info.report(0.0).degenerate);
}

}  // namespace
