#include "ring_curvature/ros/param_loading.hpp"

namespace ring_curvature
{

RingCurvatureConfig toConfig(const Params& p)
{
  RingCurvatureConfig c = RingCurvatureConfig::__getDefault__();
  c.min_range = p.min_range;
  c.max_range = p.max_range;
  c.azimuth_resolution_deg = p.azimuth_resolution_deg;
  c.max_gap_samples = p.max_gap_samples;
  c.curvature_mode = static_cast<int>(p.curvature_mode);
  c.chord_length = p.chord_length;
  c.max_chord_samples = p.max_chord_samples;
  c.smoothness_mode = static_cast<int>(p.smoothness_mode);
  c.smoothness_window = p.smoothness_window;
  c.discontinuity_mode = static_cast<int>(p.discontinuity_mode);
  c.range_noise = p.range_noise;
  c.classifier_mode = static_cast<int>(p.classifier_mode);
  c.robust_k = p.robust_k;
  c.noise_floor_k = p.noise_floor_k;
  c.edge_min_angle_deg = p.edge_min_angle_deg;
  c.jump_min_ratio = p.jump_min_ratio;
  c.non_max_suppression = p.non_max_suppression;
  c.inter_ring_roughness = p.inter_ring_roughness;
  c.rough_smoothness_min = p.rough_smoothness_min;
  c.rough_vertical_min = p.rough_vertical_min;
  c.rough_noise_k = p.rough_noise_k;
  c.rough_range_scale = p.rough_range_scale;
  c.rough_window_fraction = p.rough_window_fraction;
  c.rough_window_half = p.rough_window_half;
  c.rough_window_rings = p.rough_window_rings;
  c.edge_vertical_support = p.edge_vertical_support;
  c.edge_support_noise = p.edge_support_noise;
  c.suppress_foliage_features = p.suppress_foliage_features;
  c.foliage_keep_silhouettes = p.foliage_keep_silhouettes;
  c.foliage_feature_fraction = p.foliage_feature_fraction;
  c.occlusion_aware_jumps = p.occlusion_aware_jumps;
  c.occlusion_min_jump = p.occlusion_min_jump;
  c.thin_objects = p.thin_objects;
  c.thin_max_width = p.thin_max_width;
  c.thin_occluded = p.thin_occluded;
  c.thin_min_range = p.thin_min_range;
  c.thin_min_stack = p.thin_min_stack;
  c.thin_max_range_step = p.thin_max_range_step;
  c.thin_range_step_ratio = p.thin_range_step_ratio;
  c.use_curvature = p.use_curvature;
  c.use_smoothness = p.use_smoothness;
  c.proximity_azimuth_factor = p.proximity_azimuth_factor;
  c.proximity_range_ratio = p.proximity_range_ratio;
  c.proximity_range_min = p.proximity_range_min;
  c.min_primitive_points = p.min_primitive_points;
  c.rough_primitives = p.rough_primitives;
  c.loam_point_format = static_cast<int>(p.loam_point_format);
  c.loam_sectors = p.loam_sectors;
  c.loam_sharp_per_sector = p.loam_sharp_per_sector;
  c.loam_less_sharp_per_sector = p.loam_less_sharp_per_sector;
  c.loam_flat_per_sector = p.loam_flat_per_sector;
  c.loam_suppression = p.loam_suppression;
  c.loam_less_flat_voxel = p.loam_less_flat_voxel;
  c.loam_occlusion_ratio = p.loam_occlusion_ratio;
  c.loam_parallel_ratio = p.loam_parallel_ratio;
  c.scan_period = p.scan_period;
  c.sweep_clockwise = p.sweep_clockwise;
  c.degeneracy_length = p.degeneracy_length;
  c.degeneracy_min_eigenvalue = p.degeneracy_min_eigenvalue;
  return c;
}

Params fromConfig(const RingCurvatureConfig& c, const Params& base)
{
  Params p = base;  // field names, time_unit, max_rings, ring_from_elevation, duplicate_azimuth_fraction: start-up only
  p.min_range = static_cast<float>(c.min_range);
  p.max_range = static_cast<float>(c.max_range);
  p.azimuth_resolution_deg = static_cast<float>(c.azimuth_resolution_deg);
  p.max_gap_samples = c.max_gap_samples;
  // The .cfg enums use the same integer values as the C++ enums.
  p.curvature_mode = static_cast<CurvatureMode>(c.curvature_mode);
  p.chord_length = static_cast<float>(c.chord_length);
  p.max_chord_samples = c.max_chord_samples;
  p.smoothness_mode = static_cast<SmoothnessMode>(c.smoothness_mode);
  p.smoothness_window = c.smoothness_window;
  p.discontinuity_mode = static_cast<DiscontinuityMode>(c.discontinuity_mode);
  p.range_noise = static_cast<float>(c.range_noise);
  p.classifier_mode = static_cast<ClassifierMode>(c.classifier_mode);
  p.robust_k = static_cast<float>(c.robust_k);
  p.noise_floor_k = static_cast<float>(c.noise_floor_k);
  p.edge_min_angle_deg = static_cast<float>(c.edge_min_angle_deg);
  p.jump_min_ratio = static_cast<float>(c.jump_min_ratio);
  p.non_max_suppression = c.non_max_suppression;
  p.inter_ring_roughness = c.inter_ring_roughness;
  p.rough_smoothness_min = static_cast<float>(c.rough_smoothness_min);
  p.rough_vertical_min = static_cast<float>(c.rough_vertical_min);
  p.rough_noise_k = static_cast<float>(c.rough_noise_k);
  p.rough_range_scale = static_cast<float>(c.rough_range_scale);
  p.rough_window_fraction = static_cast<float>(c.rough_window_fraction);
  p.rough_window_half = c.rough_window_half;
  p.rough_window_rings = c.rough_window_rings;
  p.edge_vertical_support = c.edge_vertical_support;
  p.edge_support_noise = static_cast<float>(c.edge_support_noise);
  p.suppress_foliage_features = c.suppress_foliage_features;
  p.foliage_keep_silhouettes = c.foliage_keep_silhouettes;
  p.foliage_feature_fraction = static_cast<float>(c.foliage_feature_fraction);
  p.occlusion_aware_jumps = c.occlusion_aware_jumps;
  p.occlusion_min_jump = static_cast<float>(c.occlusion_min_jump);
  p.thin_objects = c.thin_objects;
  p.thin_max_width = static_cast<float>(c.thin_max_width);
  p.thin_occluded = c.thin_occluded;
  p.thin_min_range = static_cast<float>(c.thin_min_range);
  p.thin_min_stack = c.thin_min_stack;
  p.thin_max_range_step = static_cast<float>(c.thin_max_range_step);
  p.thin_range_step_ratio = static_cast<float>(c.thin_range_step_ratio);
  p.use_curvature = c.use_curvature;
  p.use_smoothness = c.use_smoothness;
  p.proximity_azimuth_factor = static_cast<float>(c.proximity_azimuth_factor);
  p.proximity_range_ratio = static_cast<float>(c.proximity_range_ratio);
  p.proximity_range_min = static_cast<float>(c.proximity_range_min);
  p.min_primitive_points = c.min_primitive_points;
  p.rough_primitives = c.rough_primitives;
  p.loam_point_format = static_cast<LoamPointFormat>(c.loam_point_format);
  p.loam_sectors = c.loam_sectors;
  p.loam_sharp_per_sector = c.loam_sharp_per_sector;
  p.loam_less_sharp_per_sector = c.loam_less_sharp_per_sector;
  p.loam_flat_per_sector = c.loam_flat_per_sector;
  p.loam_suppression = c.loam_suppression;
  p.loam_less_flat_voxel = static_cast<float>(c.loam_less_flat_voxel);
  p.loam_occlusion_ratio = static_cast<float>(c.loam_occlusion_ratio);
  p.loam_parallel_ratio = static_cast<float>(c.loam_parallel_ratio);
  p.scan_period = static_cast<float>(c.scan_period);
  p.sweep_clockwise = c.sweep_clockwise;
  p.degeneracy_length = static_cast<float>(c.degeneracy_length);
  p.degeneracy_min_eigenvalue = static_cast<float>(c.degeneracy_min_eigenvalue);
  return p;
}

}  // namespace ring_curvature
