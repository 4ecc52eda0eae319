// makePrimitiveMarkers on a hand-made PrimitiveSet over a hand-made cloud in velodyne's packed
// 22-byte layout (unaligned floats), so the geometry expected here is known exactly.
#include <gtest/gtest.h>

#include <Eigen/Geometry>  // cross()

#include <cmath>
#include <cstring>
#include <map>
#include <string>
#include <vector>

#include "ring_curvature/ros/markers.hpp"

namespace rc = ring_curvature;
using visualization_msgs::Marker;

namespace
{

constexpr std::uint32_t kStep = 22;  // x y z intensity (float32), ring (uint16), time (float32)

struct Cloud
{
  std::vector<std::uint8_t> bytes;
  rc::PointCloudView view;

  explicit Cloud(const std::vector<Eigen::Vector3f>& pts)
  {
    bytes.assign(pts.size() * kStep, 0);
    for (std::size_t i = 0; i < pts.size(); ++i)
      std::memcpy(bytes.data() + i * kStep, pts[i].data(), 3 * sizeof(float));
    view.data = bytes.data();
    view.data_size = bytes.size();
    view.width = static_cast<std::uint32_t>(pts.size());
    view.height = 1;
    view.point_step = kStep;
    view.row_step = static_cast<std::uint32_t>(bytes.size());
    view.x.offset = 0;
    view.y.offset = 4;
    view.z.offset = 8;
  }
};

void addPrimitive(rc::PrimitiveSet& set, rc::Label label, const std::vector<std::uint32_t>& idx,
                  const std::vector<Eigen::Vector3f>& pts, const Eigen::Vector3f& axis)
{
  rc::PrimitiveInfo p;
  p.id = static_cast<std::uint32_t>(set.primitives.size());
  p.label = label;
  p.num_points = static_cast<std::uint32_t>(idx.size());
  p.first = static_cast<std::uint32_t>(set.indices.size());
  Eigen::Vector3f c = Eigen::Vector3f::Zero();
  for (auto i : idx)
    c += pts[i];
  p.centroid = c / static_cast<float>(idx.size());
  p.covariance.setZero();  // (as the core's: about the mean, over the points)
  for (auto i : idx)
    p.covariance += (pts[i] - p.centroid) * (pts[i] - p.centroid).transpose();
  p.covariance /= static_cast<float>(idx.size());
  p.axis = axis;
  set.indices.insert(set.indices.end(), idx.begin(), idx.end());
  set.primitives.push_back(p);
}

Eigen::Vector3d vec(const geometry_msgs::Point& p) { return {p.x, p.y, p.z}; }

void expectColour(const std_msgs::ColorRGBA& c, rc::Label label)
{
  const rc::Rgb8 want = rc::kLabelPalette[static_cast<std::size_t>(label)];
  EXPECT_NEAR(c.r * 255.0, want.r, 0.5);
  EXPECT_NEAR(c.g * 255.0, want.g, 0.5);
  EXPECT_NEAR(c.b * 255.0, want.b, 0.5);
  EXPECT_GT(c.a, 0.0f);
}

/// Scene: a plane patch on the wall x = 5 (2 m wide in y, 1 m tall), an edge chain along z
/// given out of order, and a corner cluster of two points.
struct Scene
{
  std::vector<Eigen::Vector3f> pts;
  rc::PrimitiveSet set;
  std_msgs::Header header;

  Scene()
  {
    for (int iy = 0; iy <= 4; ++iy)
      for (int iz = 0; iz <= 2; ++iz)
        pts.emplace_back(5.0f, -1.0f + 0.5f * static_cast<float>(iy), 0.5f * static_cast<float>(iz));
    std::vector<std::uint32_t> plane(pts.size());
    for (std::uint32_t i = 0; i < plane.size(); ++i)
      plane[i] = i;
    addPrimitive(set, rc::Label::Plane, plane, pts, Eigen::Vector3f(-1, 0, 0));

    const auto e0 = static_cast<std::uint32_t>(pts.size());
    for (float z : {0.6f, -0.2f, 1.0f, 0.2f})  // deliberately not in order along the edge
      pts.emplace_back(3.0f, 2.0f, z);
    addPrimitive(set, rc::Label::Edge, {e0, e0 + 1, e0 + 2, e0 + 3}, pts, Eigen::Vector3f(0, 0, -1));

    const auto c0 = static_cast<std::uint32_t>(pts.size());
    pts.emplace_back(1.0f, 1.0f, 0.0f);
    pts.emplace_back(1.1f, 1.0f, 0.0f);
    addPrimitive(set, rc::Label::Corner, {c0, c0 + 1}, pts, Eigen::Vector3f(1, 0, 0));

    header.frame_id = "velodyne";
    header.stamp = ros::Time(1234, 5678);
    header.seq = 7;
  }
};

std::map<std::string, const Marker*> byNs(const visualization_msgs::MarkerArray& arr)
{
  std::map<std::string, const Marker*> m;
  for (const auto& mk : arr.markers)
    if (mk.action == Marker::ADD)
      m[mk.ns] = &mk;
  return m;
}

}  // namespace

TEST(Markers, PaletteColoursAreFarApart)
{
  // The screenshot checker tells labels apart by colour: every pair must differ clearly.
  for (std::size_t i = 0; i < rc::kLabelPalette.size(); ++i)
    for (std::size_t j = i + 1; j < rc::kLabelPalette.size(); ++j)
    {
      const auto& a = rc::kLabelPalette[i];
      const auto& b = rc::kLabelPalette[j];
      const double d = std::hypot(a.r - b.r, a.g - b.g, a.b - b.b);
      EXPECT_GT(d, 100.0) << "labels " << i << " and " << j;
    }
}

TEST(Markers, StartsWithDeleteAllAndKeepsHeader)
{
  Scene s;
  Cloud cloud(s.pts);
  auto arr = rc::makePrimitiveMarkers(s.set, cloud.view, s.header);
  ASSERT_TRUE(arr);
  ASSERT_FALSE(arr->markers.empty());
  EXPECT_EQ(arr->markers.front().action, Marker::DELETEALL);
  for (std::size_t i = 1; i < arr->markers.size(); ++i)
  {
    EXPECT_EQ(arr->markers[i].action, Marker::ADD);
    EXPECT_EQ(arr->markers[i].header.frame_id, "velodyne");
    EXPECT_EQ(arr->markers[i].header.stamp, s.header.stamp);
  }
  // plane quad + its normal + edge + corner
  EXPECT_EQ(arr->markers.size(), 5u);
}

TEST(Markers, EmptySetOnlyClears)
{
  Scene s;
  Cloud cloud(s.pts);
  auto arr = rc::makePrimitiveMarkers(rc::PrimitiveSet(), cloud.view, s.header);
  ASSERT_EQ(arr->markers.size(), 1u);
  EXPECT_EQ(arr->markers[0].action, Marker::DELETEALL);
}

TEST(Markers, PlanePatchCoversItsPointsInItsPlane)
{
  Scene s;
  Cloud cloud(s.pts);
  auto arr = rc::makePrimitiveMarkers(s.set, cloud.view, s.header);
  auto ns = byNs(*arr);
  ASSERT_TRUE(ns.count(rc::kPlaneNs));
  const Marker& quad = *ns[rc::kPlaneNs];
  EXPECT_EQ(quad.type, Marker::TRIANGLE_LIST);
  EXPECT_EQ(quad.id, 0);
  expectColour(quad.color, rc::Label::Plane);
  ASSERT_EQ(quad.points.size(), 12u);  // two triangles, each in both windings
  // the two windings of each triangle face opposite ways
  auto normal = [&](std::size_t t) {
    const Eigen::Vector3d a = vec(quad.points[3 * t]), b = vec(quad.points[3 * t + 1]),
                          c = vec(quad.points[3 * t + 2]);
    const Eigen::Vector3d ab = b - a, ac = c - a;
    return ab.cross(ac).normalized();
  };
  EXPECT_NEAR(normal(0).dot(normal(2)), -1.0, 1e-5);
  EXPECT_NEAR(normal(1).dot(normal(3)), -1.0, 1e-5);
  double ymin = 1e9, ymax = -1e9, zmin = 1e9, zmax = -1e9;
  for (const auto& p : quad.points)
  {
    EXPECT_NEAR(p.x, 5.0, 1e-5);  // in the wall's plane
    ymin = std::min(ymin, p.y);
    ymax = std::max(ymax, p.y);
    zmin = std::min(zmin, p.z);
    zmax = std::max(zmax, p.z);
  }
  // Spans exactly the points' extent: y in [-1, 1], z in [0, 1].
  EXPECT_NEAR(ymin, -1.0, 1e-4);
  EXPECT_NEAR(ymax, 1.0, 1e-4);
  EXPECT_NEAR(zmin, 0.0, 1e-4);
  EXPECT_NEAR(zmax, 1.0, 1e-4);

  ASSERT_TRUE(ns.count(rc::kNormalNs));
  const Marker& arrow = *ns[rc::kNormalNs];
  EXPECT_EQ(arrow.type, Marker::ARROW);
  EXPECT_EQ(arrow.id, 0);
  ASSERT_EQ(arrow.points.size(), 2u);
  const Eigen::Vector3d from = vec(arrow.points[0]), to = vec(arrow.points[1]);
  EXPECT_NEAR((from - Eigen::Vector3d(5, 0, 0.5)).norm(), 0.0, 1e-5);  // at the centroid
  const Eigen::Vector3d dir = (to - from).normalized();
  EXPECT_NEAR(dir.x(), -1.0, 1e-5);  // along the given normal, towards the sensor
  EXPECT_GT((to - from).norm(), 0.2);
}

// A strip 4 m long and 0.1 m wide on the ground, diagonal to x and y: the quad follows it (from
// the primitive's covariance), an area near the strip's 0.4 m^2, where one along x and y would
// span 2.9 m by 2.9 m. The same strip without its covariance gets that axis-aligned quad.
TEST(Markers, PlanePatchFollowsItsCovariance)
{
  std::vector<Eigen::Vector3f> pts;
  const Eigen::Vector3f along = Eigen::Vector3f(1, 1, 0).normalized(), across(-along.y(), along.x(), 0);
  for (int i = 0; i <= 40; ++i)
    for (int j = 0; j <= 2; ++j)
      pts.push_back(Eigen::Vector3f(10, 3, -1.7f) + (-2.0f + 0.1f * static_cast<float>(i)) * along +
                    (-0.05f + 0.05f * static_cast<float>(j)) * across);
  std::vector<std::uint32_t> idx(pts.size());
  for (std::uint32_t i = 0; i < idx.size(); ++i) idx[i] = i;
  Cloud cloud(pts);
  const auto quadArea = [&](bool with_covariance) {
    rc::PrimitiveSet set;
    addPrimitive(set, rc::Label::Plane, idx, pts, Eigen::Vector3f(0, 0, 1));
    if (!with_covariance) set.primitives[0].covariance.setZero();
    std_msgs::Header header;
    auto arr = rc::makePrimitiveMarkers(set, cloud.view, header);
    auto ns = byNs(*arr);
    EXPECT_TRUE(ns.count(rc::kPlaneNs));
    if (!ns.count(rc::kPlaneNs)) return 0.0;
    const Marker& quad = *ns[rc::kPlaneNs];
    EXPECT_EQ(quad.points.size(), 12u);
    if (quad.points.size() != 12u) return 0.0;
    // triangles (a, b, d) and (a, d, e): the first two of the list
    double area = 0;
    for (std::size_t t = 0; t < 2; ++t)
      area += 0.5 * (vec(quad.points[3 * t + 1]) - vec(quad.points[3 * t]))
                        .cross(vec(quad.points[3 * t + 2]) - vec(quad.points[3 * t]))
                        .norm();
    return area;
  };
  const double a = quadArea(true);
  EXPECT_GT(a, 0.39);
  EXPECT_LT(a, 0.45);
  EXPECT_GT(quadArea(false), 7.0);
}

TEST(Markers, EdgeChainIsOrderedAlongItsAxis)
{
  Scene s;
  Cloud cloud(s.pts);
  auto arr = rc::makePrimitiveMarkers(s.set, cloud.view, s.header);
  auto ns = byNs(*arr);
  ASSERT_TRUE(ns.count(rc::kEdgeNs));
  const Marker& line = *ns[rc::kEdgeNs];
  EXPECT_EQ(line.type, Marker::LINE_STRIP);
  EXPECT_EQ(line.id, 1);
  expectColour(line.color, rc::Label::Edge);
  ASSERT_EQ(line.points.size(), 4u);
  // axis is -z, so the strip runs from the top (z = 1.0) down to the bottom (z = -0.2)
  const std::vector<double> want{1.0, 0.6, 0.2, -0.2};
  for (std::size_t i = 0; i < want.size(); ++i)
  {
    EXPECT_NEAR(line.points[i].z, want[i], 1e-6);
    EXPECT_NEAR(line.points[i].x, 3.0, 1e-6);
    EXPECT_NEAR(line.points[i].y, 2.0, 1e-6);
  }
  EXPECT_GT(line.scale.x, 0.0);
}

TEST(Markers, CornerClusterIsSphereListOfItsPoints)
{
  Scene s;
  Cloud cloud(s.pts);
  auto arr = rc::makePrimitiveMarkers(s.set, cloud.view, s.header);
  auto ns = byNs(*arr);
  ASSERT_TRUE(ns.count(rc::kCornerNs));
  const Marker& spheres = *ns[rc::kCornerNs];
  EXPECT_EQ(spheres.type, Marker::SPHERE_LIST);
  EXPECT_EQ(spheres.id, 2);
  expectColour(spheres.color, rc::Label::Corner);
  ASSERT_EQ(spheres.points.size(), 2u);
  EXPECT_NEAR(spheres.points[0].x, 1.0, 1e-6);
  EXPECT_NEAR(spheres.points[1].x, 1.1, 1e-6);
  EXPECT_GT(spheres.scale.x, 0.0);
}

TEST(Markers, RoughClusterIsGreen)
{
  Scene s;
  Cloud cloud(s.pts);
  rc::PrimitiveSet set;
  addPrimitive(set, rc::Label::Rough, {0, 1, 2}, s.pts, Eigen::Vector3f(0, 1, 0));
  auto arr = rc::makePrimitiveMarkers(set, cloud.view, s.header);  // byNs points into it: keep it alive
  auto ns = byNs(*arr);
  ASSERT_TRUE(ns.count(rc::kRoughNs));
  expectColour(ns[rc::kRoughNs]->color, rc::Label::Rough);
  EXPECT_EQ(ns[rc::kRoughNs]->points.size(), 3u);
}

TEST(Markers, IndicesOutsideTheCloudAreSkipped)
{
  Scene s;
  // A cloud with fewer points than the primitives refer to: the plane (indices 0..14) still
  // fits, the edge and the corner do not and must be skipped, not read out of bounds.
  std::vector<Eigen::Vector3f> few(s.pts.begin(), s.pts.begin() + 15);
  Cloud cloud(few);
  auto arr = rc::makePrimitiveMarkers(s.set, cloud.view, s.header);
  auto ns = byNs(*arr);
  EXPECT_TRUE(ns.count(rc::kPlaneNs));
  EXPECT_FALSE(ns.count(rc::kEdgeNs));
  EXPECT_FALSE(ns.count(rc::kCornerNs));
}

TEST(Markers, NonFinitePointsAreLeftOut)
{
  Scene s;
  const float nan = std::nanf("");
  s.pts[s.set.indices[s.set.primitives[2].first]] = Eigen::Vector3f(nan, nan, nan);
  Cloud cloud(s.pts);
  auto arr = rc::makePrimitiveMarkers(s.set, cloud.view, s.header);  // byNs points into it: keep it alive
  auto ns = byNs(*arr);
  ASSERT_TRUE(ns.count(rc::kCornerNs));
  ASSERT_EQ(ns[rc::kCornerNs]->points.size(), 1u);
  EXPECT_NEAR(ns[rc::kCornerNs]->points[0].x, 1.1, 1e-6);
}

TEST(Markers, ReadsFloat64Coordinates)
{
  // PCL-style double clouds exist (e.g. some survey drivers): the view's field types are honoured.
  Scene s;
  std::vector<std::uint8_t> bytes(s.pts.size() * 24);
  for (std::size_t i = 0; i < s.pts.size(); ++i)
    for (int k = 0; k < 3; ++k)
    {
      const double v = s.pts[i][k];
      std::memcpy(bytes.data() + i * 24 + 8 * k, &v, sizeof v);
    }
  rc::PointCloudView view;
  view.data = bytes.data();
  view.data_size = bytes.size();
  view.width = static_cast<std::uint32_t>(s.pts.size());
  view.height = 1;
  view.point_step = 24;
  view.row_step = static_cast<std::uint32_t>(bytes.size());
  view.x = {0, rc::ScalarType::Float64};
  view.y = {8, rc::ScalarType::Float64};
  view.z = {16, rc::ScalarType::Float64};
  auto arr = rc::makePrimitiveMarkers(s.set, view, s.header);  // byNs points into it: keep it alive
  auto ns = byNs(*arr);
  ASSERT_TRUE(ns.count(rc::kEdgeNs));
  EXPECT_NEAR(ns[rc::kEdgeNs]->points.front().z, 1.0, 1e-6);
}

int main(int argc, char** argv)
{
  testing::InitGoogleTest(&argc, argv);
  return RUN_ALL_TESTS();
}
