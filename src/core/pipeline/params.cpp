#include "ring_curvature/params.hpp"

#include <cmath>
#include <sstream>

namespace ring_curvature
{

namespace
{
// Builds "parameter 'name' = value is out of range [lo, hi]: why".
template <typename T>
Status outOfRange(const char* name, T value, T lo, T hi, const char* why)
{
  std::ostringstream s;
  s << "parameter '" << name << "' = " << value << " is out of range [" << lo << ", " << hi << "]: " << why;
  return Status::error(s.str());
}
template <typename T>
bool inRange(T v, T lo, T hi)
{
  return v >= lo && v <= hi;  // false for NaN
}

// A field list must name at least one field and no empty one ("ring,,line" is a typo).
Status checkFieldList(const char* name, const std::string& list)
{
  const bool has_empty = forEachFieldName(list, [](std::string_view n) { return n.empty(); });
  if (has_empty)
    return Status::error(std::string("parameter '") + name + "' = '" + list +
                         "' holds an empty name: give field names separated by commas, e.g. 'ring,channel'");
  return Status::success();
}
}  // namespace

#define RC_CHECK(name, lo, hi, why) \
  if (!inRange(name, decltype(name)(lo), decltype(name)(hi))) \
    return outOfRange(#name, name, decltype(name)(lo), decltype(name)(hi), why);

Status Params::validate() const
{
  if (Status s = checkFieldList("ring_field", ring_field); !s)
    return s;
  if (Status s = checkFieldList("time_field", time_field); !s)
    return s;
  RC_CHECK(max_rings, 1, 4096, "number of rings accepted per frame");
  RC_CHECK(min_range, 0.0f, 1000.0f, "metres");
  RC_CHECK(max_range, 0.01f, 10000.0f, "metres");
  if (!(max_range > min_range))
    return Status::error("parameter 'max_range' must be greater than 'min_range'");
  RC_CHECK(azimuth_resolution_deg, 0.0f, 10.0f, "degrees, 0 = measure");
  RC_CHECK(max_gap_samples, 0, 1000, "samples");
  RC_CHECK(duplicate_azimuth_fraction, 0.0f, 0.9f, "fraction of the azimuth resolution");
  RC_CHECK(chord_length, 0.0f, 100.0f, "metres");
  RC_CHECK(max_chord_samples, 1, 256, "samples");
  RC_CHECK(smoothness_window, 1, 256, "samples on each side");
  RC_CHECK(range_noise, 0.0f, 10.0f, "metres");
  RC_CHECK(robust_k, 0.0f, 100.0f, "MAD multiples");
  RC_CHECK(noise_floor_k, 0.0f, 100.0f, "noise sigmas");
  RC_CHECK(edge_min_angle_deg, 0.0f, 180.0f, "degrees");
  RC_CHECK(jump_min_ratio, 0.0f, 10.0f, "depth jump / range");
  RC_CHECK(rough_smoothness_min, 0.0f, 100.0f, "m^2");
  RC_CHECK(rough_vertical_min, 0.0f, 100.0f, "metres");
  RC_CHECK(rough_noise_k, 0.0f, 100.0f, "multiples of the lower quartile");
  RC_CHECK(rough_range_scale, 0.0f, 1000.0f, "metres, 0 = no range scaling");
  RC_CHECK(rough_window_fraction, 0.0f, 1.0f, "share of the window");
  RC_CHECK(rough_window_half, 1, 4, "samples each way along the ring");
  RC_CHECK(rough_window_rings, 0, 2, "rings above and below, 0 = by the ring count");
  RC_CHECK(edge_support_noise, 0.0f, 10.0f, "metres");
  RC_CHECK(foliage_feature_fraction, 0.0f, 1.0f, "share of the window");
  RC_CHECK(occlusion_min_jump, 0.0f, 100.0f, "metres");
  RC_CHECK(thin_max_width, 0.0f, 100.0f, "metres");
  RC_CHECK(thin_min_range, 0.0f, 1000.0f, "metres");
  RC_CHECK(thin_min_stack, 1, 4, "samples of the 4 above and below");
  RC_CHECK(thin_max_range_step, 0.0f, 100.0f, "metres");
  RC_CHECK(thin_range_step_ratio, 0.0f, 1.0f, "range difference / range");
  RC_CHECK(loam_sectors, 1, 360, "sectors per ring");
  RC_CHECK(loam_sharp_per_sector, 0, 100000, "points per sector");
  RC_CHECK(loam_less_sharp_per_sector, 0, 100000, "points per sector");
  if (loam_less_sharp_per_sector < loam_sharp_per_sector)
    return Status::error("parameter 'loam_less_sharp_per_sector' must be >= 'loam_sharp_per_sector' "
                         "(the less sharp set holds the sharp one)");
  RC_CHECK(loam_flat_per_sector, 0, 100000, "points per sector");
  RC_CHECK(loam_suppression, 0, 1000, "samples on each side");
  RC_CHECK(loam_rough_jump, 0.0f, 10.0f, "discontinuity D, 0 = no Rough points");
  RC_CHECK(loam_less_flat_voxel, 0.0f, 100.0f, "metres, 0 = no downsampling");
  RC_CHECK(loam_occlusion_ratio, 0.0f, 10.0f, "depth jump / range");
  RC_CHECK(loam_parallel_ratio, 0.0f, 10.0f, "range step / range");
  RC_CHECK(scan_period, 0.001f, 0.999f, "seconds; the LOAM intensity ring + time needs it below 1");
  RC_CHECK(degeneracy_length, 0.01f, 1000.0f, "metres");
  RC_CHECK(degeneracy_min_eigenvalue, 0.0f, 1.0f, "information per constraint");
  RC_CHECK(proximity_azimuth_factor, 0.0f, 100.0f, "azimuth resolutions");
  RC_CHECK(proximity_range_ratio, 0.0f, 10.0f, "fraction of range");
  RC_CHECK(proximity_range_min, 0.0f, 100.0f, "metres");
  RC_CHECK(min_primitive_points, 1, 100000000, "points");
  int cm = static_cast<int>(curvature_mode), sm = static_cast<int>(smoothness_mode);
  int dm = static_cast<int>(discontinuity_mode), km = static_cast<int>(classifier_mode);
  RC_CHECK(cm, 0, 2, "curvature_mode: 0 paper, 1 developed, 2 chord");
  RC_CHECK(sm, 0, 1, "smoothness_mode: 0 variance, 1 detrended");
  RC_CHECK(dm, 0, 1, "discontinuity_mode: 0 paper, 1 jump");
  RC_CHECK(km, 0, 1, "classifier_mode: 0 quartile, 1 robust");
  int tu = static_cast<int>(time_unit);
  RC_CHECK(tu, 0, 4, "time_unit: 0 auto, 1 s, 2 ms, 3 us, 4 ns");
  int lf = static_cast<int>(loam_point_format);
  RC_CHECK(lf, 0, 1, "loam_point_format: 0 xyzi, 1 input");
  return Status::success();
}
#undef RC_CHECK

const char* toString(CurvatureMode m)
{
  switch (m)
  {
    case CurvatureMode::Paper: return "paper";
    case CurvatureMode::Developed: return "developed";
    case CurvatureMode::Chord: return "chord";
  }
  return "?";
}
const char* toString(SmoothnessMode m) { return m == SmoothnessMode::Variance ? "variance" : "detrended"; }
const char* toString(DiscontinuityMode m) { return m == DiscontinuityMode::Paper ? "paper" : "jump"; }
const char* toString(ClassifierMode m) { return m == ClassifierMode::Quartile ? "quartile" : "robust"; }
const char* toString(TimeUnit u)
{
  switch (u)
  {
    case TimeUnit::Auto: return "auto";
    case TimeUnit::S: return "s";
    case TimeUnit::Ms: return "ms";
    case TimeUnit::Us: return "us";
    case TimeUnit::Ns: return "ns";
  }
  return "?";
}

const char* toString(LoamPointFormat f) { return f == LoamPointFormat::Xyzi ? "xyzi" : "input"; }

double secondsPerUnit(TimeUnit u)
{
  switch (u)
  {
    case TimeUnit::Auto: return 0.0;
    case TimeUnit::S: return 1.0;
    case TimeUnit::Ms: return 1e-3;
    case TimeUnit::Us: return 1e-6;
    case TimeUnit::Ns: return 1e-9;
  }
  return 0.0;
}

namespace
{
template <typename E, int N>
bool parseEnum(const std::string& s, E& out)
{
  for (int i = 0; i < N; ++i)
    if (s == toString(static_cast<E>(i)))
    {
      out = static_cast<E>(i);
      return true;
    }
  return false;
}
}  // namespace

bool parse(const std::string& s, CurvatureMode& out) { return parseEnum<CurvatureMode, 3>(s, out); }
bool parse(const std::string& s, SmoothnessMode& out) { return parseEnum<SmoothnessMode, 2>(s, out); }
bool parse(const std::string& s, DiscontinuityMode& out) { return parseEnum<DiscontinuityMode, 2>(s, out); }
bool parse(const std::string& s, ClassifierMode& out) { return parseEnum<ClassifierMode, 2>(s, out); }
bool parse(const std::string& s, TimeUnit& out) { return parseEnum<TimeUnit, 5>(s, out); }
bool parse(const std::string& s, LoamPointFormat& out) { return parseEnum<LoamPointFormat, 2>(s, out); }

}  // namespace ring_curvature
