#include "ring_curvature/ros/param_table.hpp"

namespace ring_curvature
{

namespace
{

template <class Enum>
bool visitEnum(ParamVisitor& v, const char* key, Enum& value, const char* choices)
{
  std::string name = toString(value);
  if (!v.visit(key, name))
    return false;
  if (parse(name, value))
    return true;
  // dynamic_reconfigure stores enums as integers on the parameter server: accept those too.
  for (int k = 0; k < 8; ++k)
  {
    const auto e = static_cast<Enum>(k);
    Enum back;
    if (name == std::to_string(k) && parse(toString(e), back) && back == e)
    {
      value = e;
      return true;
    }
  }
  {
    v.error = std::string("parameter '") + key + "': unknown value '" + name + "' (one of " + choices + ")";
    return false;
  }
  return true;
}

// Lists keys without a Params, for isParamKey.
class KeyCollector : public ParamVisitor
{
public:
  explicit KeyCollector(const std::string& wanted) : wanted_(wanted) {}
  bool visit(const char* key, float&) override { return note(key); }
  bool visit(const char* key, int&) override { return note(key); }
  bool visit(const char* key, bool&) override { return note(key); }
  bool visit(const char* key, std::string&) override { return note(key); }
  bool found = false;

private:
  bool note(const char* key)
  {
    found = found || wanted_ == key;
    return true;
  }
  const std::string& wanted_;
};

}  // namespace

Status forEachParam(Params& p, ParamVisitor& v)
{
  const bool ok =
      v.visit("ring_field", p.ring_field) && v.visit("time_field", p.time_field) &&
      visitEnum(v, "time_unit", p.time_unit, "auto, s, ms, us, ns") &&
      v.visit("max_rings", p.max_rings) && v.visit("min_range", p.min_range) && v.visit("max_range", p.max_range) &&
      v.visit("ring_from_elevation", p.ring_from_elevation) &&
      v.visit("azimuth_resolution_deg", p.azimuth_resolution_deg) &&
      v.visit("max_gap_samples", p.max_gap_samples) &&
      v.visit("duplicate_azimuth_fraction", p.duplicate_azimuth_fraction) &&
      visitEnum(v, "curvature_mode", p.curvature_mode, "paper, developed, chord") &&
      v.visit("chord_length", p.chord_length) && v.visit("max_chord_samples", p.max_chord_samples) &&
      visitEnum(v, "smoothness_mode", p.smoothness_mode, "variance, detrended") &&
      v.visit("smoothness_window", p.smoothness_window) &&
      visitEnum(v, "discontinuity_mode", p.discontinuity_mode, "paper, jump") &&
      v.visit("range_noise", p.range_noise) &&
      visitEnum(v, "classifier_mode", p.classifier_mode, "quartile, robust") && v.visit("robust_k", p.robust_k) &&
      v.visit("noise_floor_k", p.noise_floor_k) && v.visit("edge_min_angle_deg", p.edge_min_angle_deg) &&
      v.visit("jump_min_ratio", p.jump_min_ratio) && v.visit("non_max_suppression", p.non_max_suppression) &&
      v.visit("use_curvature", p.use_curvature) && v.visit("use_smoothness", p.use_smoothness) &&
      v.visit("inter_ring_roughness", p.inter_ring_roughness) &&
      v.visit("rough_smoothness_min", p.rough_smoothness_min) &&
      v.visit("rough_vertical_min", p.rough_vertical_min) &&
      v.visit("rough_noise_k", p.rough_noise_k) &&
      v.visit("rough_range_scale", p.rough_range_scale) &&
      v.visit("rough_window_fraction", p.rough_window_fraction) &&
      v.visit("rough_window_half", p.rough_window_half) &&
      v.visit("rough_window_rings", p.rough_window_rings) &&
      v.visit("edge_vertical_support", p.edge_vertical_support) &&
      v.visit("edge_support_noise", p.edge_support_noise) &&
      v.visit("suppress_foliage_features", p.suppress_foliage_features) &&
      v.visit("foliage_keep_silhouettes", p.foliage_keep_silhouettes) &&
      v.visit("foliage_feature_fraction", p.foliage_feature_fraction) &&
      v.visit("occlusion_aware_jumps", p.occlusion_aware_jumps) &&
      v.visit("occlusion_min_jump", p.occlusion_min_jump) &&
      v.visit("thin_objects", p.thin_objects) &&
      v.visit("thin_max_width", p.thin_max_width) &&
      v.visit("thin_occluded", p.thin_occluded) &&
      v.visit("thin_min_range", p.thin_min_range) &&
      v.visit("thin_min_stack", p.thin_min_stack) &&
      v.visit("thin_max_range_step", p.thin_max_range_step) &&
      v.visit("thin_range_step_ratio", p.thin_range_step_ratio) &&
      v.visit("proximity_azimuth_factor", p.proximity_azimuth_factor) &&
      v.visit("proximity_range_ratio", p.proximity_range_ratio) &&
      v.visit("proximity_range_min", p.proximity_range_min) &&
      v.visit("min_primitive_points", p.min_primitive_points) && v.visit("rough_primitives", p.rough_primitives) &&
      visitEnum(v, "loam_point_format", p.loam_point_format, "xyzi, input") &&
      v.visit("loam_sectors", p.loam_sectors) && v.visit("loam_sharp_per_sector", p.loam_sharp_per_sector) &&
      v.visit("loam_less_sharp_per_sector", p.loam_less_sharp_per_sector) &&
      v.visit("loam_flat_per_sector", p.loam_flat_per_sector) && v.visit("loam_suppression", p.loam_suppression) &&
      v.visit("loam_rough_jump", p.loam_rough_jump) &&
      v.visit("loam_less_flat_voxel", p.loam_less_flat_voxel) &&
      v.visit("loam_occlusion_ratio", p.loam_occlusion_ratio) &&
      v.visit("loam_parallel_ratio", p.loam_parallel_ratio) && v.visit("scan_period", p.scan_period) &&
      v.visit("sweep_clockwise", p.sweep_clockwise) && v.visit("degeneracy_length", p.degeneracy_length) &&
      v.visit("degeneracy_min_eigenvalue", p.degeneracy_min_eigenvalue);
  return ok ? Status::success() : Status::error(v.error);
}

bool isParamKey(const std::string& key)
{
  Params p;
  KeyCollector c(key);
  forEachParam(p, c);
  return c.found;
}

}  // namespace ring_curvature
