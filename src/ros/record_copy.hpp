// Copies of one input record for the output clouds (outputs.cpp, label_subsets.cpp). Private to
// ring_curvature_ros; inline and templates, so each copy stays inlined in its caller's loop.
#pragma once

#include <cstddef>
#include <cstdint>
#include <cstring>

namespace ring_curvature
{
namespace detail
{

// Zeroes the padding between an input record and its appended fields (0 to 3 bytes, before
// base): a zero word ending at base, written before the record, which overwrites its own part.
inline void padRecord(std::uint8_t* rec, std::size_t base)
{
  const std::uint32_t zero = 0;
  std::memcpy(rec + base - 4, &zero, 4);
}

// Copies one record of `n` bytes. Records are small (22 bytes for a velodyne XYZIRT, 48 for an
// ouster point), too small for a memcpy call with a run-time size each: whole 8-byte words
// instead, the last one overlapping its predecessor.
struct RunTimeCopy
{
  std::size_t n;
  void operator()(std::uint8_t* dst, const std::uint8_t* src) const
  {
    if (n < 8)
    {
      std::memcpy(dst, src, n);
      return;
    }
    std::uint64_t w;
    for (std::size_t k = 0; k + 8 < n; k += 8)
    {
      std::memcpy(&w, src + k, 8);
      std::memcpy(dst + k, &w, 8);
    }
    std::memcpy(&w, src + n - 8, 8);
    std::memcpy(dst + n - 8, &w, 8);
  }
  // The record, then zeros up to `base`, its length rounded up to 4 bytes (see padRecord).
  void padded(std::uint8_t* dst, const std::uint8_t* src, std::size_t base) const
  {
    padRecord(dst, base);
    (*this)(dst, src);
  }
};

// The common record sizes with the size known to the compiler: a few inline moves per record
// instead of the word loop (velodyne XYZIRT 22 bytes, ouster 48).
template <std::size_t N>
struct FixedCopy
{
  void operator()(std::uint8_t* dst, const std::uint8_t* src) const { std::memcpy(dst, src, N); }
  // As RunTimeCopy::padded (base: N rounded up to 4). The velodyne record's last 8 bytes shifted
  // down two bytes are bytes 16 .. 21 and its two zero padding bytes (little-endian): one store
  // instead of two, as the labelled cloud's pass is bound by its stores.
  void padded(std::uint8_t* dst, const std::uint8_t* src, std::size_t base) const
  {
    if constexpr (N % 4 == 0)
    {
      (void)base;
      std::memcpy(dst, src, N);
    }
#if defined(__BYTE_ORDER__) && __BYTE_ORDER__ == __ORDER_LITTLE_ENDIAN__
    else if constexpr (N == 22)
    {
      (void)base;
      std::memcpy(dst, src, 16);
      std::uint64_t w;
      std::memcpy(&w, src + 14, 8);
      w >>= 16;
      std::memcpy(dst + 16, &w, 8);
    }
#endif
    else
    {
      padRecord(dst, base);
      std::memcpy(dst, src, N);
    }
  }
};

// Calls f(copier) with the copier for records of `n` bytes.
template <class F>
void withCopier(std::size_t n, F f)
{
  switch (n)
  {
    case 22:
      f(FixedCopy<22>());
      break;
    case 48:
      f(FixedCopy<48>());
      break;
    default:
      f(RunTimeCopy{n});
  }
}

}  // namespace detail
}  // namespace ring_curvature
