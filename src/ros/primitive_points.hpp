// The points of one primitive read in place from the cloud, for the markers (markers.cpp): the
// finite ones into scratch arrays, or a plane patch's extents in its own frame. Private to
// ring_curvature_ros; inline and templates, so the gather stays inlined in the marker loop.
#pragma once

#include "ring_curvature/prefetch.hpp"
#include "ring_curvature/primitives.hpp"
#include "ring_curvature/ros/markers.hpp"
#include "ring_curvature/types.hpp"

#include <Eigen/Core>
#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <cstring>

namespace ring_curvature
{
namespace detail
{

// Four floats per operation (GCC/Clang vector extension). The operations are element-wise IEEE
// single precision, so every lane rounds exactly as the scalar code does.
typedef float Float4 __attribute__((vector_size(16)));
inline void store4(float* p, Float4 v) { std::memcpy(p, &v, sizeof v); }

/// The finite points of one primitive as three coordinate arrays (the plane loops below then
/// work on four points per instruction), held in the scratch buffers (MarkerScratch).
struct Points
{
  const float *x, *y, *z;
  std::size_t size;
  Eigen::Vector3f operator[](std::size_t k) const { return Eigen::Vector3f(x[k], y[k], z[k]); }
};

/// Eigen's `(p - c).dot(w)` (summed as d0 w0 + (d1 w1 + d2 w2)) spelled out for floats and Float4
/// alike: the same rounding, without the expression templates' cost on every point of a plane.
template <class T>
inline T dotWith(T dx, T dy, T dz, const Eigen::Vector3f& w)
{
  return dx * w.x() + (dy * w.y() + dz * w.z());
}

/// A plane patch's frame (planeFrame): its unit normal n, its in-plane principal directions u
/// and v, its centroid.
struct PlaneFrame
{
  Eigen::Vector3f n, u, v;
  float cx, cy, cz;
};

/// Where pointsOf puts the points it keeps, in order (`m`: how many it kept before them): the
/// scratch buffers (edges and clusters, which draw the points themselves)...
struct StoredPoints
{
  float *xs, *ys, *zs;
  void one(std::size_t m, float x, float y, float z)
  {
    xs[m] = x;
    ys[m] = y;
    zs[m] = z;
  }
  void four(std::size_t m, Float4 x, Float4 y, Float4 z)
  {
    store4(xs + m, x);
    store4(ys + m, y);
    store4(zs + m, z);
  }
};

/// ... or a plane patch's extents along u and v about its centroid, bounded as the points are read
/// (no second pass over stored points). Four running bounds a side (four points at a time), merged
/// at the end: with std::min / std::max's own test (NaN never wins) and bounds starting at +0 (-0
/// never replaces it), the same bits in any order.
struct PlaneExtents
{
  PlaneFrame f;
  Float4 umin4 = {}, umax4 = {}, vmin4 = {}, vmax4 = {};
  float umin = 0, umax = 0, vmin = 0, vmax = 0;
  void one(std::size_t, float x, float y, float z)
  {
    const float dx = x - f.cx, dy = y - f.cy, dz = z - f.cz;
    const float du = dotWith(dx, dy, dz, f.u), dv = dotWith(dx, dy, dz, f.v);
    umin = std::min(umin, du);
    umax = std::max(umax, du);
    vmin = std::min(vmin, dv);
    vmax = std::max(vmax, dv);
  }
  void four(std::size_t, Float4 x, Float4 y, Float4 z)
  {
    const Float4 dx = x - f.cx, dy = y - f.cy, dz = z - f.cz;
    const Float4 du = dotWith(dx, dy, dz, f.u), dv = dotWith(dx, dy, dz, f.v);
    umin4 = du < umin4 ? du : umin4;
    umax4 = umax4 < du ? du : umax4;
    vmin4 = dv < vmin4 ? dv : vmin4;
    vmax4 = vmax4 < dv ? dv : vmax4;
  }
  void merge()
  {
    for (int l = 0; l < 4; ++l)
    {
      umin = std::min(umin, umin4[l]);
      umax = std::max(umax, umax4[l]);
      vmin = std::min(vmin, vmin4[l]);
      vmax = std::max(vmax, vmax4[l]);
    }
  }
};

/// How many points ahead pointsOf asks for the input records it will read (see there).
constexpr std::size_t kPrefetch = 32;

/// pointsOf for the clouds its float32 loop does not take (other coordinate types, padded rows):
/// store(x, y, z) for indices [first, end) in order. False when an index or record is out of range.
template <class Store>
inline bool readRecords(const PrimitiveSet& prims, std::size_t first, std::size_t end, const PointCloudView& cloud,
                        bool flat, bool float32, Store& store)
{
  const std::uint8_t* const data = cloud.data;
  const std::size_t step = cloud.point_step;
  const std::size_t size = cloud.size(), data_size = cloud.data_size;
  const std::uint32_t* const idx = prims.indices.data();
  for (std::size_t k = first; k < end; ++k)
  {
    const std::uint32_t i = idx[k];
    if (i >= size)
      return false;
    const std::uint8_t* rec = flat ? data + i * step : cloud.record(i);
    if (static_cast<std::size_t>(rec - data) + step > data_size)
      return false;
    if (float32)
      store(readFloat32(rec + cloud.x.offset), readFloat32(rec + cloud.y.offset), readFloat32(rec + cloud.z.offset));
    else
      store(static_cast<float>(readScalar(rec + cloud.x.offset, cloud.x.type)),
            static_cast<float>(readScalar(rec + cloud.y.offset, cloud.y.type)),
            static_cast<float>(readScalar(rec + cloud.z.offset, cloud.z.type)));
  }
  return true;
}

/// Reads the finite points of one primitive in place, in order, into `keep` (StoredPoints or
/// PlaneExtents) through a local copy, which the float stores cannot alias. Returns how many, or 0
/// when an index is out of range (primitives of another cloud: draw nothing rather than garbage).
template <class Keep>
std::size_t pointsOf(const PrimitiveSet& prims, const PrimitiveInfo& prim, const PointCloudView& cloud,
                     Keep& keep_out)
{
  const std::size_t end = static_cast<std::size_t>(prim.first) + prim.num_points;
  if (end > prims.indices.size() || cloud.data == nullptr || !cloud.x.present() ||
      !cloud.y.present() || !cloud.z.present())
    return 0;
  const bool float32 = cloud.x.type == ScalarType::Float32 && cloud.y.type == ScalarType::Float32 &&
                       cloud.z.type == ScalarType::Float32;
  // Rows without padding (every cloud makeView accepts): record i starts at i * point_step, the
  // same address record(i) computes with a division and a modulo per point.
  const std::uint8_t* const data = cloud.data;
  const std::size_t step = cloud.point_step;
  const bool flat = cloud.height == 1 || cloud.row_step == static_cast<std::size_t>(cloud.width) * step;
  const std::size_t size = cloud.size(), data_size = cloud.data_size;
  // Everything the loop reads held in locals, so that no member of the view is reloaded per
  // point (planes hold most points of a frame).
  Keep keep = keep_out;
  std::size_t m = 0;
  const std::uint32_t* const idx = prims.indices.data();
  // Keeps a point when its three coordinates are finite. x - x is +0 for a finite x and NaN
  // otherwise: one test for the three, where isfinite (or Eigen's allFinite) tests each.
  const auto store = [&](float x, float y, float z) {
    if ((x - x) + (y - y) + (z - z) != 0.0f)
      return;
    keep.one(m, x, y, z);
    ++m;
  };
  if (float32 && flat)
  {
    // float32 (every driver) read inline: readScalar is a call and a switch per coordinate.
    // One bound per point: i < size and i * step + step <= data_size together.
    const std::size_t limit = step == 0 ? size : std::min(size, data_size / step);
    const std::uint8_t* const px = data + cloud.x.offset;
    const std::uint8_t* const py = data + cloud.y.offset;
    const std::uint8_t* const pz = data + cloud.z.offset;
    const std::size_t num_indices = prims.indices.size();
    std::size_t k = prim.first;
    // Four points at a time (planes hold most points of a frame): one bound test, one finiteness
    // test and three 4-wide stores for the four (x - x etc. as in `store`, lane by lane: a finite
    // point sums to +0, all zero bits).
    for (; k + 4 <= end; k += 4)
    {
      const std::size_t i0 = idx[k], i1 = idx[k + 1], i2 = idx[k + 2], i3 = idx[k + 3];
      if (std::max(std::max(i0, i1), std::max(i2, i3)) >= limit)
        return 0;
      // The records kPrefetch points ahead, past the primitive's end too (most are shorter): its
      // points go ring by ring, a line each, which no prefetcher predicts. The indices are not
      // checked yet: the address may lie past the cloud (prefetch.hpp). Written out here, as GCC
      // drops a call of a helper that only prefetches (no side effect).
      if (k + kPrefetch + 4 <= num_indices)
      {
        detail::prefetchForRead(px, std::size_t{idx[k + kPrefetch]} * step);
        detail::prefetchForRead(px, std::size_t{idx[k + kPrefetch + 1]} * step);
        detail::prefetchForRead(px, std::size_t{idx[k + kPrefetch + 2]} * step);
        detail::prefetchForRead(px, std::size_t{idx[k + kPrefetch + 3]} * step);
      }
      const std::size_t o0 = i0 * step, o1 = i1 * step, o2 = i2 * step, o3 = i3 * step;
      const Float4 x = {readFloat32(px + o0), readFloat32(px + o1), readFloat32(px + o2), readFloat32(px + o3)};
      const Float4 y = {readFloat32(py + o0), readFloat32(py + o1), readFloat32(py + o2), readFloat32(py + o3)};
      const Float4 z = {readFloat32(pz + o0), readFloat32(pz + o1), readFloat32(pz + o2), readFloat32(pz + o3)};
      const Float4 t = (x - x) + (y - y) + (z - z);
      std::uint64_t bits[2];
      std::memcpy(bits, &t, sizeof t);
      if ((bits[0] | bits[1]) == 0)
      {
        keep.four(m, x, y, z);
        m += 4;
      }
      else
      {
        for (int l = 0; l < 4; ++l)
          store(x[l], y[l], z[l]);
      }
    }
    for (; k < end; ++k)
    {
      const std::size_t i = idx[k];
      if (i >= limit)
        return 0;
      const std::size_t off = i * step;
      store(readFloat32(px + off), readFloat32(py + off), readFloat32(pz + off));
    }
  }
  else if (!readRecords(prims, prim.first, end, cloud, flat, float32, store))
  {
    return 0;
  }
  keep_out = keep;
  return m;
}

/// The finite points of a primitive in the scratch buffers (pointsOf).
inline Points storedPoints(const PrimitiveSet& prims, const PrimitiveInfo& prim, const PointCloudView& cloud,
                    MarkerScratch& buf)
{
  if (buf.x.size() < prim.num_points)
  {
    buf.x.resize(prim.num_points);
    buf.y.resize(prim.num_points);
    buf.z.resize(prim.num_points);
  }
  StoredPoints keep{buf.x.data(), buf.y.data(), buf.z.data()};
  const std::size_t m = pointsOf(prims, prim, cloud, keep);
  return Points{keep.xs, keep.ys, keep.zs, m};
}

/// The plane's unit normal and in-plane principal directions, from the core's covariance of its
/// points (u0^T C u0 and so on in a basis u0, v0 of the plane), not summed again over the points
/// here; false when the axis is no direction (no patch is drawn). In primitive_points.cpp.
bool planeFrame(const PrimitiveInfo& prim, PlaneFrame& f);

}  // namespace detail
}  // namespace ring_curvature
