// One list of every key of Params, walked by the loaders (ROS parameter server, flat YAML file)
// so that the keys, their types and their defaults cannot drift apart between them.
#pragma once

#include <string>

#include "ring_curvature/params.hpp"

namespace ring_curvature
{

/// Receives each key with a reference to its value in a Params (holding the default on entry).
/// Enums are passed as their names (toString / parse). Each visit returns false on an error
/// it has already described in `error`.
class ParamVisitor
{
public:
  virtual ~ParamVisitor() = default;
  virtual bool visit(const char* key, float& value) = 0;
  virtual bool visit(const char* key, int& value) = 0;
  virtual bool visit(const char* key, bool& value) = 0;
  virtual bool visit(const char* key, std::string& value) = 0;
  std::string error;
};

/// Walks every key of `p` in declaration order; stops at the first failing visit or unknown
/// enum name and returns an error naming the key.
Status forEachParam(Params& p, ParamVisitor& visitor);

/// True when `key` is one of the keys forEachParam visits.
bool isParamKey(const std::string& key);

}  // namespace ring_curvature
