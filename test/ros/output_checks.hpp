// Checks shared by the ROS tests: what every output of one input frame must satisfy.
// Independent of the code under test: fields are read back by name through the message's own
// field table, and every expectation comes from the input cloud or the message contract.
#pragma once

#include <gtest/gtest.h>
#include <sensor_msgs/PointCloud2.h>

#include <algorithm>
#include <cstring>
#include <string>

#include "ring_curvature/PrimitiveArray.h"

namespace ring_curvature_test
{

inline const sensor_msgs::PointField* field(const sensor_msgs::PointCloud2& c, const std::string& name)
{
  for (const auto& f : c.fields)
    if (f.name == name)
      return &f;
  return nullptr;
}

inline const std::uint8_t* record(const sensor_msgs::PointCloud2& c, std::size_t i)
{
  return c.data.data() + (i / c.width) * c.row_step + (i % c.width) * c.point_step;
}

template <class T>
T get(const sensor_msgs::PointCloud2& c, std::size_t i, const sensor_msgs::PointField& f)
{
  T v;
  std::memcpy(&v, record(c, i) + f.offset, sizeof v);
  return v;
}

inline void expectSameHeader(const std_msgs::Header& in, const std_msgs::Header& out, const char* what)
{
  EXPECT_EQ(in.stamp, out.stamp) << what;
  EXPECT_EQ(in.frame_id, out.frame_id) << what;
}

/// The labelled cloud: same size, order and input fields, plus the five appended fields with
/// their datatypes; x, y, z byte-identical to the input's.
inline void checkLabelled(const sensor_msgs::PointCloud2& in, const sensor_msgs::PointCloud2& out)
{
  expectSameHeader(in.header, out.header, "labelled_points");
  ASSERT_EQ(in.width, out.width);
  ASSERT_EQ(in.height, out.height);
  for (const auto& f : in.fields)
    EXPECT_TRUE(field(out, f.name) != nullptr) << "input field " << f.name << " missing from labelled_points";
  const struct
  {
    const char* name;
    std::uint8_t type;
  } appended[] = {{"label", sensor_msgs::PointField::UINT8},
                  {"curvature", sensor_msgs::PointField::FLOAT32},
                  {"smoothness", sensor_msgs::PointField::FLOAT32},
                  {"discontinuity", sensor_msgs::PointField::FLOAT32},
                  {"primitive", sensor_msgs::PointField::INT32}};
  for (const auto& a : appended)
  {
    const auto* f = field(out, a.name);
    ASSERT_TRUE(f != nullptr) << "labelled_points has no field " << a.name;
    EXPECT_EQ(a.type, f->datatype) << a.name;
  }
  ASSERT_EQ(out.data.size(), static_cast<std::size_t>(out.row_step) * out.height);
  const std::size_t n = static_cast<std::size_t>(in.width) * in.height;
  const auto* lab = field(out, "label");
  std::size_t bad_xyz = 0, bad_label = 0;
  for (const char* axis : {"x", "y", "z"})
  {
    const auto* fi = field(in, axis);
    const auto* fo = field(out, axis);
    ASSERT_TRUE(fi && fo);
    const std::size_t size = fi->datatype == sensor_msgs::PointField::FLOAT64 ? 8 : 4;
    for (std::size_t i = 0; i < n; ++i)
      bad_xyz += std::memcmp(record(in, i) + fi->offset, record(out, i) + fo->offset, size) != 0;
  }
  for (std::size_t i = 0; i < n; ++i)
    bad_label += get<std::uint8_t>(out, i, *lab) > 4;
  EXPECT_EQ(0u, bad_xyz) << "x/y/z differ from the input (order or values changed)";
  EXPECT_EQ(0u, bad_label) << "labels outside 0..4";
}

/// Every primitive's indices carry its id in `primitive` and its label in `label`, and the
/// number of points with primitive == id equals num_points (no point claimed twice or missed).
inline void checkPrimitives(const sensor_msgs::PointCloud2& labelled, const ring_curvature::PrimitiveArray& prims)
{
  expectSameHeader(labelled.header, prims.header, "primitives");
  const auto* fp = field(labelled, "primitive");
  const auto* fl = field(labelled, "label");
  ASSERT_TRUE(fp && fl);
  const std::size_t n = static_cast<std::size_t>(labelled.width) * labelled.height;
  std::vector<std::uint32_t> count(prims.primitives.size(), 0);
  for (std::size_t i = 0; i < n; ++i)
  {
    const std::int32_t p = get<std::int32_t>(labelled, i, *fp);
    ASSERT_GE(p, -1);
    ASSERT_LT(p, static_cast<std::int32_t>(prims.primitives.size())) << "point " << i;
    if (p >= 0)
      ++count[static_cast<std::size_t>(p)];
  }
  for (std::size_t k = 0; k < prims.primitives.size(); ++k)
  {
    const auto& m = prims.primitives[k];
    ASSERT_EQ(k, m.id);
    EXPECT_GE(m.label, 1);
    EXPECT_LE(m.label, 4);
    ASSERT_EQ(m.num_points, m.indices.size());
    EXPECT_EQ(m.num_points, count[k]) << "primitive " << k;
    // the covariance is the matrix of the eigenvalues: the same trace, and for a plane its
    // variance along the normal is the least eigenvalue (to float rounding of the larger ones)
    const auto& c = m.covariance;
    const double trace = c[0] + c[3] + c[5], ev = m.eigenvalues[0] + m.eigenvalues[1] + m.eigenvalues[2];
    const double tol = 1e-4 * std::max(1e-6, ev);
    EXPECT_NEAR(trace, ev, tol) << "primitive " << k;
    EXPECT_GE(std::min({c[0], c[3], c[5]}), 0.0f) << "primitive " << k;
    if (m.label == 1)
    {
      const double nx = m.axis.x, ny = m.axis.y, nz = m.axis.z;
      const double along = nx * nx * c[0] + ny * ny * c[3] + nz * nz * c[5] +
                           2 * (nx * ny * c[1] + nx * nz * c[2] + ny * nz * c[4]);
      EXPECT_NEAR(along, m.eigenvalues[0], tol) << "primitive " << k;
    }
    for (const std::uint32_t i : m.indices)
    {
      ASSERT_LT(i, n);
      ASSERT_EQ(static_cast<std::int32_t>(k), get<std::int32_t>(labelled, i, *fp)) << "primitive " << k;
      ASSERT_EQ(m.label, get<std::uint8_t>(labelled, i, *fl)) << "primitive " << k;
    }
  }
}

/// The edge / plane clouds hold exactly the input records of the points with the given labels,
/// in input order, in the input's layout.
inline void checkSubset(const sensor_msgs::PointCloud2& in, const sensor_msgs::PointCloud2& labelled,
                        const sensor_msgs::PointCloud2& subset, std::uint8_t a, std::uint8_t b, const char* what)
{
  expectSameHeader(in.header, subset.header, what);
  ASSERT_EQ(in.point_step, subset.point_step) << what;
  ASSERT_EQ(in.fields.size(), subset.fields.size()) << what;
  const auto* fl = field(labelled, "label");
  ASSERT_TRUE(fl);
  const std::size_t n = static_cast<std::size_t>(in.width) * in.height;
  std::size_t j = 0, mismatched = 0;
  for (std::size_t i = 0; i < n; ++i)
  {
    const std::uint8_t l = get<std::uint8_t>(labelled, i, *fl);
    if (l != a && l != b)
      continue;
    if (j < subset.width)
      mismatched += std::memcmp(record(in, i), record(subset, j), in.point_step) != 0;
    ++j;
  }
  EXPECT_EQ(j, static_cast<std::size_t>(subset.width) * subset.height) << what;
  EXPECT_EQ(0u, mismatched) << what << ": records differ from the input's";
}

}  // namespace ring_curvature_test
