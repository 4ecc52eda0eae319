// Filling Params from the ROS parameter server, from a flat YAML file (process_bag) and from
// dynamic_reconfigure. Every key defaults to the value in params.hpp.
#pragma once

#include <ros/node_handle.h>

#include <map>
#include <string>

#include "ring_curvature/RingCurvatureConfig.h"
#include "ring_curvature/params.hpp"

namespace ring_curvature
{

/// Reads every key of Params from `pnh` (missing keys keep the value already in `p`), then
/// validates. A key present with the wrong type is an error naming the key.
Status loadParams(const ros::NodeHandle& pnh, Params& p);

/// Applies `key: value` strings (unknown keys are errors) onto `p`, then validates.
Status applyParamStrings(const std::map<std::string, std::string>& values, Params& p);

/// Reads a flat `key: value` YAML file (the layout of config/ring_curvature.yaml: comments,
/// blank lines, scalars only) and applies it onto `p`.
Status loadParamsFile(const std::string& path, Params& p);

/// The live-tunable subset: Params -> config (every field set) and config -> Params (keys not
/// in the .cfg keep their values from `base`).
RingCurvatureConfig toConfig(const Params& p);
Params fromConfig(const RingCurvatureConfig& c, const Params& base);

}  // namespace ring_curvature
