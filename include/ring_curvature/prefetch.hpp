// Prefetch hints at addresses that may lie past a buffer's end: the core's store streams, and
// the nodelet's cloud fill and marker gather (ros/outputs.cpp, ros/primitive_points.hpp).
//
// The core's per-point arrays are recycled from frame to frame: when a pass writes one again,
// its lines were last touched a frame ago and the stages since have pushed them out of the
// caches. Each store then waits for its line, the store buffer fills and the pass stalls on it
// (the nodelet's cloud fill has the same pattern). Asking for the lines some points ahead lets
// those fetches overlap the work.
#pragma once

#include <cstddef>
#include <cstdint>

namespace ring_curvature
{
namespace detail
{
// How far ahead of a store stream its lines are asked for, in points.
constexpr std::size_t kWriteAhead = 64;

// Prefetches, for writing, the line `offset` bytes past `p`. An integer sum: the line may lie
// past the end of the buffer, where a prefetch is harmless (it never faults) but a pointer may
// not point.
inline void prefetchForWrite(const void* p, std::size_t offset)
{
  __builtin_prefetch(reinterpret_cast<const void*>(reinterpret_cast<std::uintptr_t>(p) + offset), 1);
}
// The same for reading.
inline void prefetchForRead(const void* p, std::size_t offset)
{
  __builtin_prefetch(reinterpret_cast<const void*>(reinterpret_cast<std::uintptr_t>(p) + offset));
}

// How far ahead of their gathers the core's input passes ask for the records, in records: the
// hardware's stream prefetch does not seem to follow gathers.
constexpr std::size_t kRecordsAhead = 256;

// Asks for the `count` records from record `first` on (records of `step` bytes from `base`):
// every 64-byte line they span when a record is shorter than a line, else the line of each
// record's byte `field` (one line a record, not all of a long record's lines). One loop: GCC
// deleted the prefetches of an if / else of two loops as an empty loop nest.
inline void prefetchRecords(const void* base, std::size_t first, std::size_t count, std::size_t step,
                            std::size_t field)
{
  const std::size_t stride = step < 64 ? 64 : step, at = first * step + (step < 64 ? 0 : field);
  for (std::size_t o = 0; o < count * step; o += stride) prefetchForRead(base, at + o);
}
}  // namespace detail
}  // namespace ring_curvature
