#include "ring_curvature/ros/cloud_adapter.hpp"

#include <sensor_msgs/PointField.h>

#include <algorithm>
#include <sstream>

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

  // ring: any integer type (drivers differ: uint8, uint16, int16, int32 ...).
  if (const auto* f = findField(msg, "ring"))
  {
    toScalarType(f->datatype, view.ring.type);
    if (!isIntegerType(view.ring.type))
      return Status::error("field 'ring' is " + datatypeName(f->datatype) +
                           "; it must be an integer type (uint8/uint16/int16/int32 ...): fix the "
                           "driver's point type, or drop the field and set ~ring_from_elevation:=true");
    view.ring.offset = f->offset;
  }
  else if (msg.height <= 1 && !params.ring_from_elevation)
  {
    return Status::error("cloud has no 'ring' field (fields present: " + describeFields(msg) +
                         "); use a driver that publishes 'ring' (velodyne_pointcloud, ouster-ros, ...), "
                         "publish an organized cloud (row = ring), or set ~ring_from_elevation:=true");
  }

  // time: optional; the core passes it through, the output keeps the input's bytes anyway.
  for (const char* name : kTimeFieldNames)
  {
    const auto* f = findField(msg, name);
    if (!f)
      continue;
    if (f->datatype == sensor_msgs::PointField::FLOAT32 || f->datatype == sensor_msgs::PointField::FLOAT64 ||
        f->datatype == sensor_msgs::PointField::UINT32)
    {
      view.time.offset = f->offset;
      toScalarType(f->datatype, view.time.type);
      break;
    }
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
  return Status::success();
}

}  // namespace ring_curvature
