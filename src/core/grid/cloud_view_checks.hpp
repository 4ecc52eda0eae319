// Validation of a PointCloudView before anything reads it: sizes, field layout and types, ring
// range. Every rejection names the problem, so a bad frame gets a message a user can act on.
#pragma once

#include "ring_curvature/params.hpp"
#include "ring_curvature/types.hpp"

namespace ring_curvature
{

/// Success when every record the grid will read lies inside the buffer and the fields it needs
/// are present with usable types; an empty frame (width or height 0) is legal.
Status checkLayout(const PointCloudView& v, const Params& params);

}  // namespace ring_curvature
