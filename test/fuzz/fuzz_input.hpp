// How the fuzz target reads its bytes: a small header describing a PointCloud2 (sizes, flags,
// parameter choices, up to 8 fields) followed by the point data. test/fuzz/make_seeds.py writes
// the same format from real frames. All fields little-endian.
//
//   offset size
//   0      1   flags: bit0 is_bigendian, bit1 ring_from_elevation,
//                     bit2 row_step := width * point_step, bit3 data resized to row_step * height
//   1      1   parameter bits: 0-1 curvature mode, 2 smoothness, 3 discontinuity, 4 classifier,
//                     5 non-max suppression, 6 rough primitives, 7 fixed azimuth resolution
//   2      1   max_rings - 1
//   3      1   number of fields (mod 9)
//   4      4   width      8  4  height      12  4  point_step      16  4  row_step
//   20     8*n fields: u8 name id, u8 datatype, u16 count, u32 offset
//   ...        data
#pragma once

#include <cstdint>
#include <cstring>
#include <string>
#include <vector>

#include "ring_curvature/params.hpp"

namespace ring_curvature
{
namespace fuzz
{

struct Field
{
  std::string name;
  std::uint8_t datatype = 0;
  std::uint32_t count = 0, offset = 0;
};

struct Input
{
  std::uint8_t flags = 0, param_bits = 0;
  int max_rings = 256;
  std::uint32_t width = 0, height = 0, point_step = 0, row_step = 0;
  std::vector<Field> fields;
  std::vector<std::uint8_t> data;
};

constexpr std::size_t kHeaderSize = 20, kFieldSize = 8;
/// Largest data buffer the "resize" flag may create: keeps one execution well under a second.
constexpr std::uint64_t kMaxResizedBytes = 256 * 1024;

/// Field names the fuzzer can pick: everything the adapter looks up, and one it must ignore.
inline const char* fieldName(std::uint8_t id)
{
  static const char* const names[] = {"x", "y", "z", "ring", "time", "t", "intensity", "timestamp", "other"};
  return names[id % 9];
}

template <class T>
T load(const std::uint8_t* p)
{
  T v;
  std::memcpy(&v, p, sizeof v);
  return v;
}

/// False when there are too few bytes for the header and its fields.
inline bool decode(const std::uint8_t* bytes, std::size_t size, Input& in)
{
  if (size < kHeaderSize)
    return false;
  in.flags = bytes[0];
  in.param_bits = bytes[1];
  in.max_rings = bytes[2] + 1;
  const std::size_t nfields = bytes[3] % 9;
  in.width = load<std::uint32_t>(bytes + 4);
  in.height = load<std::uint32_t>(bytes + 8);
  in.point_step = load<std::uint32_t>(bytes + 12);
  in.row_step = load<std::uint32_t>(bytes + 16);
  if (size < kHeaderSize + nfields * kFieldSize)
    return false;
  const std::uint8_t* f = bytes + kHeaderSize;
  in.fields.resize(nfields);
  for (std::size_t i = 0; i < nfields; ++i, f += kFieldSize)
  {
    in.fields[i].name = fieldName(f[0]);
    in.fields[i].datatype = f[1];
    in.fields[i].count = load<std::uint16_t>(f + 2);
    in.fields[i].offset = load<std::uint32_t>(f + 4);
  }
  in.data.assign(f, bytes + size);
  if (in.flags & 4)
    in.row_step = static_cast<std::uint32_t>(static_cast<std::uint64_t>(in.width) * in.point_step);
  const std::uint64_t want = static_cast<std::uint64_t>(in.row_step) * in.height;
  if ((in.flags & 8) && want <= kMaxResizedBytes)
    in.data.resize(want, 0);
  return true;
}

inline Params params(const Input& in)
{
  Params p;
  p.max_rings = in.max_rings;
  p.ring_from_elevation = (in.flags & 2) != 0;
  p.curvature_mode = static_cast<CurvatureMode>((in.param_bits & 3) % 3);
  p.smoothness_mode = static_cast<SmoothnessMode>((in.param_bits >> 2) & 1);
  p.discontinuity_mode = static_cast<DiscontinuityMode>((in.param_bits >> 3) & 1);
  p.classifier_mode = static_cast<ClassifierMode>((in.param_bits >> 4) & 1);
  p.non_max_suppression = (in.param_bits >> 5) & 1;
  p.rough_primitives = (in.param_bits >> 6) & 1;
  p.azimuth_resolution_deg = (in.param_bits >> 7) & 1 ? 0.2f : 0.0f;
  p.min_primitive_points = 1;  // report every component: more code runs per input
  return p;
}

}  // namespace fuzz
}  // namespace ring_curvature
