// Building ring_curvature/PrimitiveArray messages.
//
// Why a separate record type: the message generated from msg/Primitive.msg is
// `ring_curvature::Primitive`, the same name as the core's struct in primitives.hpp, so no
// translation unit can include both. The core side (frame_processor.cpp) copies each primitive
// into a PrimitiveRecord (a few hundred per frame, cheap); this file's .cpp sees only the message.
// Drop this indirection once the core struct is renamed.
#pragma once

#include <std_msgs/Header.h>

#include <boost/shared_ptr.hpp>
#include <cstdint>
#include <memory>
#include <vector>

namespace ring_curvature
{

template <class ContainerAllocator>
struct PrimitiveArray_;
typedef boost::shared_ptr<PrimitiveArray_<std::allocator<void>>> PrimitiveArrayPtr;

/// One primitive, as plain data (mirrors ring_curvature::Primitive of the core).
struct PrimitiveRecord
{
  std::uint32_t id = 0;
  std::uint8_t label = 0;
  std::uint32_t num_points = 0;
  std::uint32_t first = 0;  ///< offset of its indices in the indices array
  float centroid[3] = {0, 0, 0}, axis[3] = {0, 0, 0}, eigenvalues[3] = {0, 0, 0};
  float bbox_min[3] = {0, 0, 0}, bbox_max[3] = {0, 0, 0};
  float rms_error = 0;
  std::uint16_t ring_min = 0, ring_max = 0;
};

/// New PrimitiveArray with `header`; indices[first, first + num_points) of each record.
PrimitiveArrayPtr makePrimitiveArray(const std_msgs::Header& header, const std::vector<PrimitiveRecord>& records,
                                     const std::vector<std::uint32_t>& indices);

}  // namespace ring_curvature
