// Every tunable of the core in one struct. Defaults live here and only here; the ROS layer
// reads each key with this value as its default (config/ring_curvature.yaml documents them).
#pragma once

#include <string>
#include <string_view>

#include "ring_curvature/types.hpp"

namespace ring_curvature
{

/// How the turning angle and arc length of Eq 9 are formed (see docs/method.md).
enum class CurvatureMode : int
{
  Paper = 0,      ///< Eq 6-9 literally: arg of dz in the z = rho e^{i theta} plane, one-sample chords
  Developed = 1,  ///< Eq 6-9 in the cone's isometric development w = rho e^{i theta cos(phi)}
  Chord = 2,      ///< developed plane, chords spanning >= chord_length metres (noise-aware scale)
};

/// How the smoothness S of Eq 10 is formed.
enum class SmoothnessMode : int
{
  Variance = 0,   ///< Eq 10: variance of range over the window
  Detrended = 1,  ///< residual variance of range after a local linear fit (flat oblique walls ~ 0)
};

/// How the discontinuity D of Eq 11 is formed.
enum class DiscontinuityMode : int
{
  Paper = 0,  ///< Eq 11: |drho| / ds, bounded in [0, 1] (sine of the ray-to-ring angle)
  Jump = 1,   ///< one-sided linear-prediction error of range over range, max over both links
};

/// How per-ring thresholds are derived from the feature distributions.
enum class ClassifierMode : int
{
  Quartile = 0,  ///< Algorithm 1 exactly: Q25 / Q75 per ring and feature
  Robust = 1,    ///< median + k * MAD per ring, floored by what sensor noise alone can produce
};

/// Unit of the per-point time field (PointCloudView::time_scale is derived from it).
/// Members are spelt as the parameter's values ("auto", "s", "ms", "us", "ns").
enum class TimeUnit : int
{
  Auto = 0,  ///< float32/float64: seconds (nanoseconds when the value exceeds 1e12); integers: nanoseconds
  S = 1,
  Ms = 2,
  Us = 3,
  Ns = 4,
};

/// Point layout of the LOAM outputs.
enum class LoamPointFormat : int
{
  Xyzi = 0,   ///< pcl::PointXYZI, intensity = ring + seconds since the sweep began (A-LOAM's)
  Input = 1,  ///< the input's own records (every field, time included)
};

struct Params
{
  // --- input layout (names of the driver's fields; start-up only) ---------------------------
  std::string ring_field = "ring,channel,line,laser_id";  ///< ring index: the first of these names present
  std::string time_field = "time,t,timestamp,time_stamp,offset_time";  ///< per-point time: the first present
  TimeUnit time_unit = TimeUnit::Auto;  ///< unit of the time field

  // --- scan grid -------------------------------------------------------------------------
  int max_rings = 256;                  ///< frames with a ring index >= this are rejected
  float min_range = 0.3f;               ///< [m] closer returns are invalid (sensor housing)
  float max_range = 250.0f;             ///< [m] farther returns are invalid
  bool ring_from_elevation = false;     ///< no ring field: cluster elevation angles into rings
  float azimuth_resolution_deg = 0.0f;  ///< [deg] 0 = measure from the data each frame
  int max_gap_samples = 2;              ///< more missing samples than this break a ring's curve
  float duplicate_azimuth_fraction = 0.3f;  ///< same-firing returns: |d az| < this * resolution

  // --- features --------------------------------------------------------------------------
  CurvatureMode curvature_mode = CurvatureMode::Chord;
  float chord_length = 0.25f;           ///< [m] Chord mode: shortest chord (0.25 measured best, docs/evaluation)
  int max_chord_samples = 6;            ///< Chord mode: longest chord, in samples
  SmoothnessMode smoothness_mode = SmoothnessMode::Detrended;
  int smoothness_window = 3;            ///< w of Eq 10: window is 2w + 1 samples
  DiscontinuityMode discontinuity_mode = DiscontinuityMode::Jump;
  float range_noise = 0.02f;            ///< [m] 1-sigma range noise of the sensor (noise floors)

  // --- classification --------------------------------------------------------------------
  ClassifierMode classifier_mode = ClassifierMode::Robust;
  float robust_k = 3.0f;                ///< Robust: threshold = median + robust_k * 1.4826 * MAD
  float noise_floor_k = 3.0f;           ///< Robust: floors are this many noise sigmas
  float edge_min_angle_deg = 30.0f;     ///< Robust: smallest turning angle called a crease
  float jump_min_ratio = 0.03f;         ///< Robust, Jump mode: smallest depth jump / range
  bool non_max_suppression = true;      ///< Robust: keep only the peak of an Edge/Corner run
  bool use_curvature = true;            ///< ablation (paper Table 2, Ours-NoCurv): false ignores kappa
  bool use_smoothness = true;           ///< ablation (paper Table 2, Ours-NoSmooth): false ignores S

  // --- inter-ring evidence (the paper's section 6.2; all off = the ring-wise labels) -----------
  bool inter_ring_roughness = true;     ///< Rough decided over a window of rings x samples (below)
  int rough_window_half = 4;            ///< the window: this many samples each way along the ring
  int rough_window_rings = 0;           ///< ... on the ring itself and this many rings above and below (0: 2 with >= 32 rings, else 1)
  float rough_smoothness_min = 4e-5f;   ///< [m^2] least bound on S (x (range / rough_range_scale)^2) called rough along the ring
  float rough_vertical_min = 0.012f;    ///< [m] least bound on the cross-ring range residual (x range / scale) called rough
  float rough_noise_k = 3.0f;           ///< both bounds at least this multiple of the frame's lower-quartile value (S: squared)
  float rough_range_scale = 10.0f;      ///< [m] both bounds grow with range beyond this (0: never)
  float rough_window_fraction = 0.5f;   ///< Rough where at least this share of the window is rough both ways
  bool edge_vertical_support = true;    ///< in a noisy frame an Edge needs an Edge/Corner beside it on the ring above or below
  float edge_support_noise = 0.015f;    ///< [m] ... a frame whose range noise (from the cross-ring residual) is above this
  bool suppress_foliage_features = true;   ///< no Edge/Corner inside rough surroundings
  float foliage_feature_fraction = 0.3f;  ///< an Edge/Corner with this share of its window rough becomes Rough
  bool foliage_keep_silhouettes = true;  ///< ... unless it is the near side of a jump stacked over rings (a trunk's outline)
  bool occlusion_aware_jumps = true;    ///< only the near side of a depth jump is a Corner
  float occlusion_min_jump = 0.10f;     ///< [m] smallest depth jump (and jump_min_ratio * range)
  bool thin_objects = true;             ///< narrow runs in front of both neighbours, stacked over rings: Edge
  float thin_max_width = 0.7f;          ///< [m] widest such run (poles, trunks, signs)
  bool thin_occluded = true;            ///< a run hidden on one side by a nearer object (a pole behind another) counts too
  float thin_min_range = 2.0f;          ///< [m] nearer runs are not thin objects (clutter around the sensor)
  int thin_min_stack = 4;               ///< of the 4 samples above and below (2 rings each way), how many must be such runs
  float thin_max_range_step = 0.2f;     ///< [m] range difference to a stacked sample
  float thin_range_step_ratio = 0.02f;  ///< ... or this share of the range, if larger (rings spread with range)

  // --- primitives (section 4.3) ----------------------------------------------------------
  float proximity_azimuth_factor = 1.5f;  ///< Eq 19: d theta_tol = factor * azimuth resolution
  float proximity_range_ratio = 0.02f;    ///< Eq 20: d rho_tol = max(ratio * mean rho, min)
  float proximity_range_min = 0.10f;      ///< [m] Eq 20
  int min_primitive_points = 3;           ///< smaller components are not reported
  bool rough_primitives = false;          ///< also report connected Rough clusters

  // --- LOAM feature sets (loam_features.hpp; built only while a LOAM output is wanted) ---------
  LoamPointFormat loam_point_format = LoamPointFormat::Xyzi;
  int loam_sectors = 6;                   ///< equal parts of each ring, each with its own quotas
  int loam_sharp_per_sector = 2;          ///< sharpest Edge/Corner points per sector
  int loam_less_sharp_per_sector = 20;    ///< less sharp (these hold the sharp ones)
  int loam_flat_per_sector = 4;           ///< flattest Plane points per sector
  int loam_suppression = 5;               ///< a chosen point blocks this many ring neighbours each side
  float loam_rough_jump = 0.1f;           ///< Rough points at a depth jump (D above this) are less sharp too (0: none)
  float loam_less_flat_voxel = 0.2f;      ///< [m] less flat: one Plane point per voxel and ring (0: all)
  float loam_occlusion_ratio = 0.1f;      ///< depth jump / nearer range above which the far side is occluded
  float loam_parallel_ratio = 0.02f;      ///< range steps / range to both neighbours above which the surface runs along the beam
  float scan_period = 0.1f;               ///< [s] one sweep (the fraction of the LOAM intensity)
  bool sweep_clockwise = true;            ///< sweep direction, for times from azimuth (Velodyne, Ouster: clockwise)
  float degeneracy_length = 10.0f;        ///< [m] a rotation counts as the motion it gives at this range
  float degeneracy_min_eigenvalue = 0.007f;  ///< weakest direction's information per constraint below this: degenerate

  /// Checks ranges and consistency; the message names the offending parameter.
  Status validate() const;
};

const char* toString(CurvatureMode m);
const char* toString(SmoothnessMode m);
const char* toString(DiscontinuityMode m);
const char* toString(ClassifierMode m);
const char* toString(TimeUnit u);
const char* toString(LoamPointFormat f);
/// Parse the names printed by toString (case-sensitive); false when unknown.
bool parse(const std::string& s, CurvatureMode& out);
bool parse(const std::string& s, SmoothnessMode& out);
bool parse(const std::string& s, DiscontinuityMode& out);
bool parse(const std::string& s, ClassifierMode& out);
bool parse(const std::string& s, TimeUnit& out);
bool parse(const std::string& s, LoamPointFormat& out);

/// Seconds per unit of an explicitly set time unit; 0 for TimeUnit::Auto (decided per cloud).
double secondsPerUnit(TimeUnit u);

/// Calls `f(name)` for each name of a comma-separated field list (ring_field, time_field), blanks
/// around a name trimmed, until `f` returns true; returns whether one did. Allocates nothing, so
/// the adapter can walk the list every frame.
template <class F>
bool forEachFieldName(std::string_view list, F&& f)
{
  while (true)
  {
    const std::size_t comma = list.find(',');
    std::string_view name = list.substr(0, comma);
    const std::size_t b = name.find_first_not_of(" \t");
    name = b == std::string_view::npos ? std::string_view() : name.substr(b, name.find_last_not_of(" \t") - b + 1);
    if (f(name))
      return true;
    if (comma == std::string_view::npos)
      return false;
    list.remove_prefix(comma + 1);
  }
}

}  // namespace ring_curvature
