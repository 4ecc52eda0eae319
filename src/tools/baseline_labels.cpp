// rosrun ring_curvature baseline_labels --input IN.bag --output OUT.bag --method pca|euclid
//                                       [--topic T]
// Labels every PointCloud2 of a bag with one of the PCL baselines and writes it on
// /ring_curvature/labelled_points (every input field plus `label`, uint8), the topic and layout
// the nodelet and process_bag use, so the evaluation scores the baselines exactly like ours.
#include <sensor_msgs/PointCloud2.h>

#include <cstdio>
#include <iostream>
#include <string>
#include <vector>

#include "bag_clouds.hpp"
#include "bench_label_cloud.hpp"
#include "baselines/euclidean_clustering.hpp"
#include "baselines/pca_curvature.hpp"
#include "option_pairs.hpp"
#include "ring_curvature/ros/cloud_adapter.hpp"

namespace rc = ring_curvature;

int main(int argc, char** argv)
{
  std::string input, output, method, topic;
  if (!rc::bench::readOptionPairs(argc, argv, "baseline_labels",
                                  {{"--input", rc::bench::into(input)},
                                   {"--output", rc::bench::into(output)},
                                   {"--method", rc::bench::into(method)},
                                   {"--topic", rc::bench::into(topic)}}))
    return 2;
  if (argc % 2 == 0 || input.empty() || output.empty() || (method != "pca" && method != "euclid"))
  {
    std::cerr << "usage: baseline_labels --input IN.bag --output OUT.bag --method pca|euclid [--topic T]\n";
    return 2;
  }

  rc::baselines::PcaCurvature pca;
  rc::baselines::EuclideanClustering euclid;
  rc::Params lenient;
  lenient.ring_from_elevation = true;
  std::size_t frames = 0, skipped = 0, points = 0;
  std::size_t counts[rc::kNumLabels] = {};
  try
  {
    rosbag::Bag in(input, rosbag::bagmode::Read);
    rosbag::Bag out(output, rosbag::bagmode::Write);
    rosbag::View view;
    rc::bench::addCloudQuery(view, in, topic);
    std::vector<std::uint8_t> labels;
    for (const rosbag::MessageInstance& m : view)
    {
      const auto cloud = m.instantiate<sensor_msgs::PointCloud2>();
      if (!cloud)
        continue;
      rc::PointCloudView v;
      // the nodelet's own adapter; the baselines need no ring, so ring-less clouds are accepted
      const rc::Status st = rc::makeView(*cloud, lenient, v);
      if (!st)
      {
        std::cerr << "baseline_labels: skipping a frame on " << m.getTopic() << ": " << st.message << "\n";
        ++skipped;
        continue;
      }
      if (method == "pca")
        pca.label(v, labels);
      else
        euclid.label(v, labels);
      sensor_msgs::PointCloud2 labelled;
      rc::bench::appendLabelField(*cloud, labels, labelled);
      out.write("/ring_curvature/labelled_points", m.getTime(), labelled);
      ++frames;
      points += labels.size();
      for (const auto l : labels)
        ++counts[l < rc::kNumLabels ? l : 0];
    }
  }
  catch (const std::exception& e)
  {
    std::cerr << "baseline_labels: " << e.what() << "\n";
    return 1;
  }
  std::printf("baseline_labels: %s wrote %zu frames (%zu skipped), %zu points: plane %zu, edge %zu, "
              "corner %zu, rough %zu, none %zu -> %s\n",
              method.c_str(), frames, skipped, points, counts[1], counts[2], counts[3], counts[4], counts[0],
              output.c_str());
  return frames > 0 ? 0 : 1;
}
