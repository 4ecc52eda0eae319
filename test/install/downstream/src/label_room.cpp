// A user's program on the installed package: a VLP-16-like scan of a box room as a
// sensor_msgs/PointCloud2, read in place by the ROS adapter, labelled by the core, its primitives
// turned into a ring_curvature/PrimitiveArray and its LOAM sets chosen. Exits non-zero when any
// of that fails or gives labels that a box room cannot have.
#include <ring_curvature/PrimitiveArray.h>
#include <ring_curvature/pipeline.hpp>
#include <ring_curvature/ros/cloud_adapter.hpp>
#include <ring_curvature/ros/primitive_message.hpp>

#include <sensor_msgs/point_cloud2_iterator.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>

namespace rc = ring_curvature;

namespace
{
constexpr int kRings = 16, kColumns = 1800;

// Distance along the unit ray d from the origin to the inside of the box [lo, hi].
double toWalls(const double d[3])
{
  const double lo[3] = {-6.0, -5.0, -1.5}, hi[3] = {8.0, 4.0, 2.5};
  double t = std::numeric_limits<double>::infinity();
  for (int a = 0; a < 3; ++a)
    if (d[a] != 0.0) t = std::min(t, (d[a] > 0 ? hi[a] : lo[a]) / d[a]);
  return t;
}

sensor_msgs::PointCloud2 roomScan()
{
  sensor_msgs::PointCloud2 msg;
  msg.header.frame_id = "velodyne";
  sensor_msgs::PointCloud2Modifier mod(msg);
  mod.setPointCloud2Fields(6, "x", 1, sensor_msgs::PointField::FLOAT32, "y", 1, sensor_msgs::PointField::FLOAT32,
                           "z", 1, sensor_msgs::PointField::FLOAT32, "intensity", 1, sensor_msgs::PointField::FLOAT32,
                           "ring", 1, sensor_msgs::PointField::UINT16, "time", 1, sensor_msgs::PointField::FLOAT32);
  mod.resize(static_cast<std::size_t>(kRings) * kColumns);
  sensor_msgs::PointCloud2Iterator<float> x(msg, "x"), y(msg, "y"), z(msg, "z"), t(msg, "time");
  sensor_msgs::PointCloud2Iterator<std::uint16_t> ring(msg, "ring");
  // Firing order: column by column, every ring in each, as a Velodyne driver emits them.
  for (int c = 0; c < kColumns; ++c)
    for (int r = 0; r < kRings; ++r, ++x, ++y, ++z, ++t, ++ring)
    {
      const double el = (-15.0 + 2.0 * r) * M_PI / 180.0, az = 2.0 * M_PI * c / kColumns;
      const double d[3] = {std::cos(el) * std::cos(az), std::cos(el) * std::sin(az), std::sin(el)};
      const double range = toWalls(d);
      *x = static_cast<float>(range * d[0]);
      *y = static_cast<float>(range * d[1]);
      *z = static_cast<float>(range * d[2]);
      *t = static_cast<float>(0.1 * c / kColumns);
      *ring = static_cast<std::uint16_t>(r);
    }
  return msg;
}

int fail(const char* what)
{
  std::fprintf(stderr, "label_room: FAIL: %s\n", what);
  return 1;
}
}  // namespace

int main()
{
  const sensor_msgs::PointCloud2 msg = roomScan();
  const rc::Params params;
  rc::PointCloudView view;
  const rc::Status adapted = rc::makeView(msg, params, view);
  if (!adapted) return fail(adapted.message.c_str());
  rc::Pipeline pipeline(params);
  rc::FrameResult result;
  const rc::Status processed = pipeline.process(view, result);
  if (!processed) return fail(processed.message.c_str());
  rc::LoamFeatures loam;
  pipeline.selectLoamFeatures(view, loam);
  const auto primitives = rc::makePrimitiveArray(msg.header, result.primitives);

  const auto& n = result.label_counts;
  const auto count = [&n](rc::Label l) { return n[static_cast<std::size_t>(l)]; };
  std::printf("label_room: %zu points, plane %zu, edge %zu, corner %zu, rough %zu, primitives %zu, "
              "LOAM sharp %zu flat %zu\n",
              view.size(), count(rc::Label::Plane), count(rc::Label::Edge), count(rc::Label::Corner),
              count(rc::Label::Rough), primitives->primitives.size(), loam.sharp.size(), loam.flat.size());
  // Six flat faces and four vertical creases: mostly Plane, creases found, nothing rough.
  if (count(rc::Label::Plane) < view.size() * 9 / 10) return fail("fewer than 90 % of the room's points are Plane");
  if (count(rc::Label::Edge) + count(rc::Label::Corner) == 0) return fail("no Edge or Corner at the room's creases");
  if (count(rc::Label::Rough) > view.size() / 100) return fail("more than 1 % of a noise-free room is Rough");
  if (primitives->primitives.size() != result.primitives.primitives.size() || primitives->primitives.empty())
    return fail("the PrimitiveArray does not hold the frame's primitives");
  if (loam.sharp.empty() || loam.flat.empty()) return fail("no LOAM sharp or flat points");
  return 0;
}
