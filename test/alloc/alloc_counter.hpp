// Counts heap allocations made by this process while counting is switched on. The test binary
// interposes malloc and friends (glibc resolves them to the executable's definitions first), so
// every allocation is seen: operator new, Eigen's aligned malloc, and those inside shared libraries.
#pragma once

#include <cstddef>

namespace ring_curvature
{
namespace test
{

/// False where malloc cannot be interposed (sanitizer builds provide their own).
bool allocCountingAvailable();
void startCountingAllocations();
/// Stops counting and returns how many allocations (malloc, calloc, realloc, aligned) were made.
std::size_t stopCountingAllocations();

}  // namespace test
}  // namespace ring_curvature
