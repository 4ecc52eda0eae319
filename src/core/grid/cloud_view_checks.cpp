#include "grid/cloud_view_checks.hpp"

#include <sstream>
#include <string>
#include <utility>

namespace ring_curvature
{

namespace
{
bool overlaps(const FieldView& a, const FieldView& b)
{
  if (!a.present() || !b.present()) return false;
  const auto ae = a.offset + static_cast<std::int64_t>(scalarSize(a.type));
  const auto be = b.offset + static_cast<std::int64_t>(scalarSize(b.type));
  return a.offset < be && b.offset < ae;
}

Status checkField(const char* name, const FieldView& f, std::uint32_t point_step)
{
  const std::size_t sz = scalarSize(f.type);
  if (sz == 0)
  {
    std::ostringstream s;
    s << "field '" << name << "' has an invalid datatype code " << static_cast<int>(f.type);
    return Status::error(s.str());
  }
  if (f.offset < 0 || static_cast<std::uint64_t>(f.offset) + sz > point_step)
  {
    std::ostringstream s;
    s << "field '" << name << "' (offset " << f.offset << ", " << sz << " bytes) lies outside the point record "
      << "(point_step " << point_step << ")";
    return Status::error(s.str());
  }
  return Status::success();
}

}  // namespace

Status checkLayout(const PointCloudView& v, const Params& params)
{
  if (v.width == 0 || v.height == 0) return Status::success();  // empty frame: legal, nothing to do
  if (v.data == nullptr) return Status::error("cloud has points but no data buffer");
  if (v.point_step == 0) return Status::error("point_step is 0");
  const std::uint64_t min_row = static_cast<std::uint64_t>(v.width) * v.point_step;
  if (v.row_step < min_row)
  {
    std::ostringstream s;
    s << "row_step " << v.row_step << " is smaller than width * point_step = " << v.width << " * " << v.point_step
      << " = " << min_row;
    return Status::error(s.str());
  }
  const std::uint64_t need = static_cast<std::uint64_t>(v.row_step) * (v.height - 1) + min_row;
  if (v.data_size < need)
  {
    std::ostringstream s;
    s << "data holds " << v.data_size << " bytes but width " << v.width << " x height " << v.height
      << " with row_step " << v.row_step << " needs " << need << " (truncated cloud)";
    return Status::error(s.str());
  }
  const struct
  {
    const char* name;
    const FieldView& f;
  } xyz[] = {{"x", v.x}, {"y", v.y}, {"z", v.z}};
  for (const auto& c : xyz)
  {
    if (!c.f.present()) return Status::error(std::string("cloud has no '") + c.name + "' field");
    if (c.f.type != ScalarType::Float32 && c.f.type != ScalarType::Float64)
      return Status::error(std::string("field '") + c.name + "' has type " + scalarTypeName(c.f.type) +
                           "; expected float32 or float64");
    Status st = checkField(c.name, c.f, v.point_step);
    if (!st) return st;
  }
  if (v.ring.present())
  {
    if (!isIntegerType(v.ring.type))
      return Status::error(std::string("field 'ring' has type ") + scalarTypeName(v.ring.type) +
                           "; expected an integer type (uint8, uint16, int16, int32, ...)");
    Status st = checkField("ring", v.ring, v.point_step);
    if (!st) return st;
  }
  else if (!v.organized() && !params.ring_from_elevation)
  {
    return Status::error("cloud has no 'ring' field and is unorganized (height 1): use a driver that publishes "
                         "the per-point ring, or set ring_from_elevation to derive rings from elevation angles");
  }
  for (const auto& c : {std::make_pair("time", &v.time), std::make_pair("intensity", &v.intensity)})
  {
    Status st = c.second->present() ? checkField(c.first, *c.second, v.point_step) : Status::success();
    if (!st) return st;
  }
  const FieldView* used[] = {&v.x, &v.y, &v.z, &v.ring};
  const char* names[] = {"x", "y", "z", "ring"};
  for (int a = 0; a < 4; ++a)
    for (int b = a + 1; b < 4; ++b)
      if (overlaps(*used[a], *used[b]))
        return Status::error(std::string("fields '") + names[a] + "' and '" + names[b] + "' overlap in the point record");
  if (v.organized() && v.height > static_cast<std::uint32_t>(params.max_rings))
  {
    std::ostringstream s;
    s << "organized cloud has " << v.height << " rows (rings) but max_rings is " << params.max_rings;
    return Status::error(s.str());
  }
  return Status::success();
}

}  // namespace ring_curvature
