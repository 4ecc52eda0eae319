// The published PCL point type reads the labelled cloud with pcl::fromROSMsg, every field.
#include <gtest/gtest.h>
#include <pcl_conversions/pcl_conversions.h>

#include <cmath>

#include "ring_curvature/point_types.hpp"
#include "ring_curvature/ros/frame_processor.hpp"
#include "cloud_builders.hpp"
#include "output_checks.hpp"

using namespace ring_curvature_test;

TEST(PointTypes, FromRosMsgReadsEveryField)
{
  const auto frames = readClouds(std::string(RC_SOURCE_DIR) + "/rosbag_fixtures/nebula_vlp16_lastreturn_4scans.bag",
                                 "/velodyne_points");
  ASSERT_FALSE(frames.empty());
  ring_curvature::FrameProcessor proc;
  ring_curvature::Outputs out;
  ASSERT_TRUE(proc.process(*frames[0], out).ok);
  const sensor_msgs::PointCloud2& m = *out.labelled;

  pcl::PointCloud<ring_curvature::PointXYZIRTLabelled> cloud;
  pcl::fromROSMsg(m, cloud);
  ASSERT_EQ(static_cast<std::size_t>(m.width) * m.height, cloud.size());
  const auto *fx = field(m, "x"), *fr = field(m, "ring"), *ft = field(m, "time"), *fl = field(m, "label"),
             *fp = field(m, "primitive"), *fc = field(m, "curvature");
  std::size_t bad = 0, labelled = 0;
  for (std::size_t i = 0; i < cloud.size(); ++i)
  {
    const auto& p = cloud[i];
    bad += p.x != get<float>(m, i, *fx);
    bad += p.ring != get<std::uint16_t>(m, i, *fr);
    bad += p.time != get<float>(m, i, *ft);
    bad += p.label != get<std::uint8_t>(m, i, *fl);
    bad += p.primitive != get<std::int32_t>(m, i, *fp);
    const float c = get<float>(m, i, *fc);
    bad += !(p.curvature == c || (std::isnan(p.curvature) && std::isnan(c)));
    labelled += p.label != 0;
  }
  EXPECT_EQ(0u, bad);
  EXPECT_GT(labelled, cloud.size() / 2);
}
