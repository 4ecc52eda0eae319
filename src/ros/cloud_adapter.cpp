#include "ring_curvature/ros/cloud_adapter.hpp"

#include <sensor_msgs/PointField.h>

#include <algorithm>
#include <cmath>
#include <sstream>
#include <string_view>

namespace ring_curvature
{

namespace
{

bool toScalarType(std::uint8_t datatype, ScalarType& out)
{
  // sensor_msgs::PointField's INT8..FLOAT64 are 1..8, the same numbering as ScalarType.
  if (datatype < sensor_msgs::PointField::INT8 || datatype > sensor_msgs::PointField::FLOAT64)
    return false;
  out = static_cast<ScalarType>(datatype);
  return true;
}

const sensor_msgs::PointField* findField(const sensor_msgs::PointCloud2& msg, const char* name)
{
  for (const auto& f : msg.fields)
    if (f.name == name)
      return &f;
  return nullptr;
}

std::string datatypeName(std::uint8_t datatype)
{
  ScalarType t;
  return toScalarType(datatype, t) ? scalarTypeName(t) : "datatype " + std::to_string(datatype);
}

// The first name of a comma-separated list (the order of the parameter, not of the message)
// that the cloud has.
const sensor_msgs::PointField* findFirstField(const sensor_msgs::PointCloud2& msg, const std::string& names)
{
  const sensor_msgs::PointField* found = nullptr;
  forEachFieldName(names, [&](std::string_view name) {
    for (const auto& f : msg.fields)
      if (f.name == name)
      {
        found = &f;
        return true;
      }
    return false;
  });
  return found;
}

// "'ring', 'channel', 'line'" for error messages.
std::string quotedNames(const std::string& names)
{
  std::string out;
  forEachFieldName(names, [&](std::string_view name) {
    out.append(out.empty() ? "'" : ", '").append(name).append("'");
    return false;
  });
  return out;
}

// ring and time are one value per point: a field with count > 1 is some other quantity.
Status checkScalar(const sensor_msgs::PointField& f, const char* role, const char* param, const std::string& list)
{
  if (f.count <= 1)
    return Status::success();
  return Status::error("field '" + f.name + "' (the " + role + ", found by ~" + param + " = '" + list + "') has count " +
                       std::to_string(f.count) + "; one value per point is expected: name another field in ~" + param);
}

// Above this a float time cannot be seconds (1e12 s is 31,700 years) but is nanoseconds: an
// absolute stamp in ns is ~1.7e18 (livox_ros_driver2 sends float64 ns), one in s ~1.7e9.
constexpr double kFloatNanosecondsAbove = 1e12;
// Records looked at for a finite time: the first ones may be invalid returns.
constexpr std::size_t kTimeProbeRecords = 64;

// time_unit "auto": integer fields count nanoseconds (ouster-ros `t`, Livox `offset_time`,
// Autoware `time_stamp`; PointField has no 64-bit integer, so they are offsets, not absolute
// stamps); float fields count seconds unless the first finite value says nanoseconds.
double timeScale(const PointCloudView& view, TimeUnit unit)
{
  if (unit != TimeUnit::Auto)
    return secondsPerUnit(unit);
  if (isIntegerType(view.time.type))
    return 1e-9;
  const std::size_t probe = std::min<std::size_t>(view.size(), kTimeProbeRecords);
  for (std::size_t i = 0; i < probe; ++i)
  {
    const double t = readScalar(view.record(i) + view.time.offset, view.time.type);
    if (std::isfinite(t))
      return std::fabs(t) > kFloatNanosecondsAbove ? 1e-9 : 1.0;
  }
  return 1.0;
}

// The message's description of its own layout holds: little-endian, sizes that agree with the
// data, every field inside the point record.
Status checkLayout(const sensor_msgs::PointCloud2& msg)
{
  if (msg.is_bigendian)
    return Status::error("cloud is big-endian (is_bigendian = true); only little-endian clouds "
                         "are supported: convert it on the producing side");

  const std::uint64_t n = static_cast<std::uint64_t>(msg.width) * msg.height;
  if (n > 0 && msg.point_step == 0)
    return Status::error("point_step is 0 for a cloud of " + std::to_string(n) + " points");
  if (static_cast<std::uint64_t>(msg.row_step) < static_cast<std::uint64_t>(msg.width) * msg.point_step)
    return Status::error("row_step " + std::to_string(msg.row_step) + " is smaller than width * point_step = " +
                         std::to_string(static_cast<std::uint64_t>(msg.width) * msg.point_step) +
                         ": the cloud's layout is inconsistent");
  const std::uint64_t expected = static_cast<std::uint64_t>(msg.row_step) * msg.height;
  if (msg.data.size() != expected)
    return Status::error("data holds " + std::to_string(msg.data.size()) + " bytes but row_step * height = " +
                         std::to_string(expected) + ": the message is truncated or its header is wrong");

  // Every field must lie inside the point record, whatever it is used for: a field past
  // point_step means the producer's layout description is wrong.
  for (const auto& f : msg.fields)
  {
    ScalarType t;
    if (!toScalarType(f.datatype, t))
      return Status::error("field '" + f.name + "' has unknown datatype " + std::to_string(f.datatype));
    const std::uint64_t end =
        static_cast<std::uint64_t>(f.offset) + scalarSize(t) * std::max<std::uint32_t>(f.count, 1u);
    if (end > msg.point_step)
      return Status::error("field '" + f.name + "' (offset " + std::to_string(f.offset) + ", " +
                           scalarTypeName(t) + " x" + std::to_string(std::max<std::uint32_t>(f.count, 1u)) +
                           ") ends past point_step " + std::to_string(msg.point_step));
  }
  return Status::success();
}

}  // namespace

std::string describeFields(const sensor_msgs::PointCloud2& msg)
{
  if (msg.fields.empty())
    return "(none)";
  std::ostringstream s;
  for (std::size_t i = 0; i < msg.fields.size(); ++i)
    s << (i ? ", " : "") << msg.fields[i].name << ':' << datatypeName(msg.fields[i].datatype);
  return s.str();
}

Status makeView(const sensor_msgs::PointCloud2& msg, const Params& params, PointCloudView& view)
{
  view = PointCloudView();
  if (Status s = checkLayout(msg); !s)
    return s;

  // x, y, z: required, float32 or float64.
  FieldView* xyz[3] = {&view.x, &view.y, &view.z};
  const char* xyz_names[3] = {"x", "y", "z"};
  for (int i = 0; i < 3; ++i)
  {
    const auto* f = findField(msg, xyz_names[i]);
    if (!f)
      return Status::error(std::string("cloud has no '") + xyz_names[i] + "' field (fields present: " +
                           describeFields(msg) + "); x, y, z are required");
    if (f->datatype != sensor_msgs::PointField::FLOAT32 && f->datatype != sensor_msgs::PointField::FLOAT64)
      return Status::error(std::string("field '") + xyz_names[i] + "' is " + datatypeName(f->datatype) +
                           "; x, y, z must be float32 or float64");
    xyz[i]->offset = f->offset;
    toScalarType(f->datatype, xyz[i]->type);
  }

  // ring: the first name of ~ring_field that the cloud has; any integer type (drivers differ:
  // uint8, uint16, int16, int32 ...). A later name is not tried when the first one present has
  // the wrong type: that field is what the user asked for, so its type is the error.
  const sensor_msgs::PointField* ring = findFirstField(msg, params.ring_field);
  if (ring)
  {
    if (Status s = checkScalar(*ring, "ring", "ring_field", params.ring_field); !s)
      return s;
    toScalarType(ring->datatype, view.ring.type);
    if (!isIntegerType(view.ring.type))
      return Status::error("field '" + ring->name + "' (the ring, found by ~ring_field = '" + params.ring_field +
                           "') is " + datatypeName(ring->datatype) +
                           "; a ring must be an integer type (uint8/uint16/int16/int32 ...): fix the driver's "
                           "point type or name the right field in ~ring_field");
    view.ring.offset = ring->offset;
  }
  else if (msg.height <= 1 && !params.ring_from_elevation)
  {
    return Status::error("cloud has no ring field: none of " + quotedNames(params.ring_field) +
                         " (parameter ~ring_field) is among the fields present (" + describeFields(msg) +
                         "); name the driver's ring field in ~ring_field, publish an organized cloud "
                         "(row = ring), or set ~ring_from_elevation:=true");
  }

  // time: optional, the first name of ~time_field present; any numeric type. The grid ignores it;
  // the LOAM outputs read it as (t - earliest t of the frame) * time_scale seconds, so both
  // times relative to the header stamp and absolute ones (Hesai, RoboSense) work.
  if (const sensor_msgs::PointField* t = findFirstField(msg, params.time_field))
  {
    if (Status s = checkScalar(*t, "time", "time_field", params.time_field); !s)
      return s;
    view.time.offset = t->offset;
    toScalarType(t->datatype, view.time.type);
  }

  if (const auto* f = findField(msg, "intensity"))
  {
    view.intensity.offset = f->offset;
    toScalarType(f->datatype, view.intensity.type);
  }

  view.data = msg.data.data();
  view.data_size = msg.data.size();
  view.width = msg.width;
  view.height = msg.height;
  view.point_step = msg.point_step;
  view.row_step = msg.row_step;
  if (view.time.present())
    view.time_scale = timeScale(view, params.time_unit);
  return Status::success();
}

}  // namespace ring_curvature
