#include "ring_curvature/ros/param_loading.hpp"
#include "ring_curvature/ros/param_table.hpp"

namespace ring_curvature
{

namespace
{
using Config = RingCurvatureConfig;

/// The member of Config that cfg/RingCurvature.cfg declares as `key` with C++ type T, or null
/// (a start-up-only key, which the .cfg does not list).
template <typename T>
T Config::*liveField(const char* key)
{
  for (const auto& d : Config::__getParamDescriptions__())
    if (d->name == key)
    {
      const auto* typed = dynamic_cast<const Config::ParamDescription<T>*>(d.get());
      return typed ? typed->field : nullptr;
    }
  return nullptr;
}

/// Copies every live number and switch between a Params and a Config, walking the one list of
/// keys (param_table.cpp), so that a new live key needs no line here. Enums: by the caller.
class LiveCopy : public ParamVisitor
{
public:
  LiveCopy(Config& config, bool to_config) : config_(config), to_config_(to_config) {}
  bool visit(const char* key, float& v) override { return copy<double>(key, v); }
  bool visit(const char* key, int& v) override { return copy<int>(key, v); }
  bool visit(const char* key, bool& v) override { return copy<bool>(key, v); }
  bool visit(const char*, std::string&) override { return true; }  // field names are start-up only

private:
  template <typename T, typename V>
  bool copy(const char* key, V& v)
  {
    if (const auto field = liveField<T>(key))
    {
      if (to_config_)
        config_.*field = static_cast<T>(v);
      else
        v = static_cast<V>(config_.*field);
    }
    return true;
  }
  Config& config_;
  const bool to_config_;
};
}  // namespace

RingCurvatureConfig toConfig(const Params& p)
{
  Config c = Config::__getDefault__();
  Params walked = p;  // (forEachParam hands out references; this direction only reads them)
  LiveCopy copy(c, true);
  forEachParam(walked, copy);
  // The .cfg enums use the same integer values as the C++ enums.
  c.curvature_mode = static_cast<int>(p.curvature_mode);
  c.smoothness_mode = static_cast<int>(p.smoothness_mode);
  c.discontinuity_mode = static_cast<int>(p.discontinuity_mode);
  c.classifier_mode = static_cast<int>(p.classifier_mode);
  c.loam_point_format = static_cast<int>(p.loam_point_format);
  return c;
}

Params fromConfig(const RingCurvatureConfig& c, const Params& base)
{
  Params p = base;  // the start-up-only keys (field names, time_unit, max_rings, ...) stay
  Config read = c;
  LiveCopy copy(read, false);
  forEachParam(p, copy);
  p.curvature_mode = static_cast<CurvatureMode>(c.curvature_mode);
  p.smoothness_mode = static_cast<SmoothnessMode>(c.smoothness_mode);
  p.discontinuity_mode = static_cast<DiscontinuityMode>(c.discontinuity_mode);
  p.classifier_mode = static_cast<ClassifierMode>(c.classifier_mode);
  p.loam_point_format = static_cast<LoamPointFormat>(c.loam_point_format);
  return p;
}

}  // namespace ring_curvature
