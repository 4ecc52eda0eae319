// Recycling of output messages between frames. Subscribers in the same process receive the
// published object itself and drop it once their callback is done; when the processor holds the
// only reference left, nobody can see the object any more, and the next frame fills it again:
// its buffers keep their capacity, so a frame allocates (and zero-fills) nothing it had before.
#pragma once

#include <boost/make_shared.hpp>
#include <boost/shared_ptr.hpp>

#include <utility>

namespace ring_curvature
{

/// `reuse` when the caller holds its only reference, else a new default message.
template <class M>
boost::shared_ptr<M> recycled(boost::shared_ptr<M> reuse)
{
  if (reuse && reuse.use_count() == 1)
    return reuse;
  return boost::make_shared<M>();
}

}  // namespace ring_curvature
