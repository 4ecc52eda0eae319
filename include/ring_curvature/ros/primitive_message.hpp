// Building ring_curvature/PrimitiveArray messages from the core's primitives.
#pragma once

#include <std_msgs/Header.h>

#include <boost/shared_ptr.hpp>
#include <memory>

#include "ring_curvature/primitives.hpp"

namespace ring_curvature
{

template <class ContainerAllocator>
struct PrimitiveArray_;
typedef boost::shared_ptr<PrimitiveArray_<std::allocator<void>>> PrimitiveArrayPtr;

/// PrimitiveArray with `header`, one message per primitive of `set` (indices copied). `reuse`: an
/// array built by an earlier call, filled again when the caller holds its only reference.
PrimitiveArrayPtr makePrimitiveArray(const std_msgs::Header& header, const PrimitiveSet& set,
                                     PrimitiveArrayPtr reuse = {});

}  // namespace ring_curvature
