// The pipeline's stages and the products they hand on, held by Pipeline (pipeline.hpp).
#pragma once

#include "classification/classifier.hpp"
#include "classification/inter_ring.hpp"
#include "grid/scan_grid_builder.hpp"
#include "features/feature_computer.hpp"
#include "loam/loam_selector.hpp"
#include "primitives/primitive_extractor.hpp"
#include "ring_curvature/pipeline.hpp"
#include "ring_curvature/scan_grid.hpp"

#include <vector>

namespace ring_curvature
{

struct Pipeline::Stages
{
  ScanGridBuilder grid_builder;
  FeatureComputer feature_computer;
  Classifier classifier;
  InterRingRefiner inter_ring;
  PrimitiveExtractor primitive_extractor;
  LoamSelector loam_selector;
  ScanGrid grid;
  Features features;
  std::vector<RingThresholds> thresholds;
  std::vector<Label> labels;
};

}  // namespace ring_curvature
