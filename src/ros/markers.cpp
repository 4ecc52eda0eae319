// Primitives of one frame as rviz markers (see markers.hpp for the shapes and the palette).

#include "ring_curvature/ros/markers.hpp"
#include "ring_curvature/ros/geometry_conversions.hpp"
#include "ring_curvature/prefetch.hpp"
#include "ring_curvature/ros/recycle.hpp"

#include <Eigen/Geometry>
#include <boost/make_shared.hpp>
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <utility>
#include <vector>

namespace ring_curvature
{
namespace
{

// Sizes in metres: thick enough to read at the 10-30 m scale of a VLP-16 scene in rviz.
constexpr double kEdgeLineWidth = 0.05;
constexpr double kCornerSphere = 0.15;
constexpr double kRoughSphere = 0.08;
constexpr double kNormalShaft = 0.03;
constexpr float kNormalMinLength = 0.3f, kNormalMaxLength = 1.0f;
constexpr float kPlaneAlpha = 0.6f;  // see-through, so the labelled points under it stay visible

std_msgs::ColorRGBA colourOf(Label label, float alpha)
{
  const Rgb8 c = kLabelPalette[static_cast<std::size_t>(label)];
  std_msgs::ColorRGBA out;
  out.r = static_cast<float>(c.r) / 255.0f;
  out.g = static_cast<float>(c.g) / 255.0f;
  out.b = static_cast<float>(c.b) / 255.0f;
  out.a = alpha;
  return out;
}


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

/// Eigen's `(p - c).dot(w)` for three floats (it sums as d0 w0 + (d1 w1 + d2 w2)) spelled out, for
/// plain floats and for four points at a time: through the expression templates every point cost
/// several times as much (perf), and the plane patches are the output whose cost grows with the
/// points.
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

/// ... or a plane patch's extents along u and v about its centroid, bounded as the points are
/// read (u and v come from the covariance, before the points): stored first and bounded in a
/// second pass, each point was written and read once more. A minimum and a maximum do not depend
/// on the order, so four running ones per bound (four points at a time), merged at the end with
/// those of single points. Each update is std::min / std::max's own test (a NaN never replaces
/// the bound), and the bounds start at +0, which a -0 never replaces: the same bits in any order.
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

/// Reads the finite points of one primitive in place from the view, in order, into `keep`
/// (StoredPoints or PlaneExtents; a local copy, written back at the end: the float stores might
/// alias the caller's object, which would then be stored and reloaded per point). Returns how
/// many, or 0 when any index is out of range (a primitive set that does not belong to this
/// cloud: draw nothing rather than garbage).
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
  // Everything the loop reads held in locals: reloads of the view's members per point showed in
  // the profile (planes hold most points of a frame).
  Keep keep = keep_out;
  std::size_t m = 0;
  const std::uint32_t* const idx = prims.indices.data();
  // Keeps a point when its three coordinates are finite. x - x is +0 for a finite x and NaN
  // otherwise: one test for the three (three isfinite tests were a quarter of the gather's
  // instructions; Eigen's allFinite does the same on a temporary vector, slower still).
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
    // Four points at a time: one bound test, one finiteness test and three 4-wide stores for the
    // four (x - x etc. as in `store`, lane by lane: a finite point sums to +0, all zero bits),
    // where a point at a time cost ~22 instructions (planes hold most points of a frame).
    for (; k + 4 <= end; k += 4)
    {
      const std::size_t i0 = idx[k], i1 = idx[k + 1], i2 = idx[k + 2], i3 = idx[k + 3];
      if (std::max(std::max(i0, i1), std::max(i2, i3)) >= limit)
        return 0;
      // The records of the points kPrefetch places ahead, asked for now: a primitive's indices
      // go ring by ring, each point on another cache line of the input, which the core read
      // long before (out of the cache by now) and which no hardware prefetcher predicts. The
      // markers took ~10 % less time (A/B of whole frames, 32 ahead; 16 gained less, 64 no more).
      // Past the primitive's end too, into the indices of the ones after it (drawn next, in
      // order): a primitive's first kPrefetch points were never asked for, and most primitives
      // have fewer. (Those indices are not checked against this cloud yet: the address may lie
      // past its end, see ring_curvature/prefetch.hpp.)
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
  else
  {
    for (std::size_t k = prim.first; k < end; ++k)
    {
      const std::uint32_t i = idx[k];
      if (i >= size)
        return 0;
      const std::uint8_t* rec = flat ? data + i * step : cloud.record(i);
      if (static_cast<std::size_t>(rec - data) + step > data_size)
        return 0;
      if (float32)
        store(readFloat32(rec + cloud.x.offset), readFloat32(rec + cloud.y.offset), readFloat32(rec + cloud.z.offset));
      else
        store(static_cast<float>(readScalar(rec + cloud.x.offset, cloud.x.type)),
              static_cast<float>(readScalar(rec + cloud.y.offset, cloud.y.type)),
              static_cast<float>(readScalar(rec + cloud.z.offset, cloud.z.type)));
    }
  }
  keep_out = keep;
  return m;
}

/// The finite points of a primitive in the scratch buffers (pointsOf).
Points storedPoints(const PrimitiveSet& prims, const PrimitiveInfo& prim, const PointCloudView& cloud,
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

// Slots::next resets a recycled marker field by field, so it must know every field: these are
// the MD5 sums of the Marker and Header definitions it was written for (a changed definition
// fails here).
static_assert(ros::message_traits::MD5Sum<visualization_msgs::Marker>::static_value1 == 0x4048c9de2a16f4aeULL &&
                  ros::message_traits::MD5Sum<visualization_msgs::Marker>::static_value2 == 0x8e0538085ebf1b97ULL,
              "visualization_msgs/Marker changed: update Slots::next to its fields");
static_assert(ros::message_traits::MD5Sum<std_msgs::Header>::static_value1 == 0x2176decaecbce78aULL &&
                  ros::message_traits::MD5Sum<std_msgs::Header>::static_value2 == 0xbc3b96ef049fabedULL,
              "std_msgs/Header changed: update Slots::next to its fields");

/// Sets `s` to the `n` characters at `v`, leaving it alone when it holds them already: a recycled
/// marker mostly does (the frame id and the namespace of the same slot last frame), and the
/// comparison costs less than the assignment (the two string assignments were half the cost of
/// a marker's fields).
void setString(std::string& s, const char* v, std::size_t n)
{
  if (s.size() != n || std::memcmp(s.data(), v, n) != 0)
    s.assign(v, n);
}

/// The markers of a frame, filled in order into an array that may hold an earlier frame's: a
/// marker already there is reset to a default one that keeps its buffers (points, strings),
/// so a recycled array allocates nothing for markers it had; the rest is cut off at the end.
struct Slots
{
  std::vector<visualization_msgs::Marker>& markers;
  std::size_t used = 0;
  /// The next marker: a default one with `header` and namespace `ns`.
  visualization_msgs::Marker& next(const std_msgs::Header& header, const char* ns)
  {
    visualization_msgs::Marker& m = used == markers.size() ? markers.emplace_back() : reset(markers[used]);
    ++used;
    m.header.seq = header.seq;
    m.header.stamp = header.stamp;
    setString(m.header.frame_id, header.frame_id.data(), header.frame_id.size());
    setString(m.ns, ns, std::strlen(ns));
    return m;
  }
  /// `m` with every field but the header and the namespace (which next sets) at its default.
  static visualization_msgs::Marker& reset(visualization_msgs::Marker& m)
  {
    // Each field set in place: assigning a default-constructed marker (with the buffers moved
    // out and back around it) cost ~300 instructions a marker, 1 % of the nodelet's samples.
    m.id = 0;
    m.type = 0;
    m.action = 0;
    m.pose = geometry_msgs::Pose();
    m.scale = geometry_msgs::Vector3();
    m.color = std_msgs::ColorRGBA();
    m.lifetime = ros::Duration();
    m.frame_locked = 0;
    m.points.clear();
    m.colors.clear();
    m.text.clear();
    m.mesh_resource.clear();
    m.mesh_use_embedded_materials = 0;
    return m;
  }
};

/// Appends a marker of `prim` to `out` and returns it for the caller to fill in. Built in place:
/// a local marker moved into the array cost a construction, a move and a destruction per marker.
visualization_msgs::Marker& addMarker(Slots& out, const std_msgs::Header& header, const char* ns,
                                      const PrimitiveInfo& prim, std::int32_t type)
{
  visualization_msgs::Marker& m = out.next(header, ns);
  m.id = static_cast<std::int32_t>(prim.id);
  m.type = type;
  m.action = visualization_msgs::Marker::ADD;
  m.pose.orientation.w = 1.0;  // points are given in the header's frame
  return m;
}

/// A unit vector perpendicular to n (n need not be normalised).
Eigen::Vector3f anyPerpendicular(const Eigen::Vector3f& n)
{
  const Eigen::Vector3f helper =
      std::abs(n.z()) < 0.9f ? Eigen::Vector3f::UnitZ() : Eigen::Vector3f::UnitX();
  return n.cross(helper).normalized();
}


/// The plane's unit normal and in-plane principal directions, from the core's covariance of its
/// points (u0^T C u0 and so on in a basis u0, v0 of the plane: where the markers summed it again
/// over the points, a chain of additions a point, that took more of the markers' time than
/// reading the points); false when the axis is no direction (no patch is drawn).
bool planeFrame(const PrimitiveInfo& prim, PlaneFrame& f)
{
  Eigen::Vector3f n = prim.axis;
  if (!(n.squaredNorm() > 0.0f) || !n.allFinite())
    return false;
  n.normalize();
  f.n = n;
  // In-plane principal direction from the points' 2-D covariance, so the quad follows the patch
  // (a wall strip seen by 16 rings is long and thin; a square would misdraw it).
  const Eigen::Vector3f u0 = anyPerpendicular(n), v0 = n.cross(u0);
  f.cx = prim.centroid.x();
  f.cy = prim.centroid.y();
  f.cz = prim.centroid.z();
  const Eigen::Matrix3f& c = prim.covariance;
  const Eigen::Vector3f cu = c * u0, cv = c * v0;
  const float cuu = u0.dot(cu), cvv = v0.dot(cv), cuv = u0.dot(cv);
  // Major axis of a 2x2 covariance in closed form (no iterative solver for two dimensions).
  const float angle = 0.5f * std::atan2(2.0f * cuv, cuu - cvv);
  f.u = (std::cos(angle) * u0 + std::sin(angle) * v0).normalized();
  f.v = n.cross(f.u);
  return true;
}

/// `ext`: the patch's extents (pointsOf into PlaneExtents, merged).
void addPlane(const PrimitiveInfo& prim, const PlaneExtents& ext, const std_msgs::Header& header, Slots& out)
{
  const Eigen::Vector3f& n = ext.f.n;
  const Eigen::Vector3f& u = ext.f.u;
  const Eigen::Vector3f& v = ext.f.v;
  float umin = ext.umin, umax = ext.umax, vmin = ext.vmin, vmax = ext.vmax;
  // A single-ring patch has no extent across the ring: give it a sliver so it is still drawn.
  const float min_half = 0.02f;
  vmin = std::min(vmin, -min_half);
  vmax = std::max(vmax, min_half);
  umin = std::min(umin, -min_half);
  umax = std::max(umax, min_half);
  const Eigen::Vector3f c = prim.centroid;
  const Eigen::Vector3f a = c + umin * u + vmin * v, b = c + umax * u + vmin * v,
                        d = c + umax * u + vmax * v, e = c + umin * u + vmax * v;

  auto& quad = addMarker(out, header, kPlaneNs, prim, visualization_msgs::Marker::TRIANGLE_LIST);
  quad.scale.x = quad.scale.y = quad.scale.z = 1.0;
  quad.color = colourOf(Label::Plane, kPlaneAlpha);
  // Both windings: rviz culls and darkens back faces, and the patch is seen from either side.
  quad.points.reserve(12);
  for (const auto* corner : {&a, &b, &d, &a, &d, &e, &a, &d, &b, &a, &e, &d})
    quad.points.push_back(toPoint(*corner));

  const float size = std::max(umax - umin, vmax - vmin);
  const float length = std::clamp(0.5f * size, kNormalMinLength, kNormalMaxLength);
  auto& arrow = addMarker(out, header, kNormalNs, prim, visualization_msgs::Marker::ARROW);
  arrow.scale.x = kNormalShaft;        // shaft diameter
  arrow.scale.y = 2.0 * kNormalShaft;  // head diameter
  arrow.scale.z = 3.0 * kNormalShaft;  // head length
  arrow.color = colourOf(Label::Plane, 1.0f);
  arrow.points.reserve(2);
  arrow.points.push_back(toPoint(c));
  arrow.points.push_back(toPoint(c + length * n));
}

void addEdge(const PrimitiveInfo& prim, const Points& chain, const std_msgs::Header& header,
             std::vector<Eigen::Vector3f>& pts, Slots& out)
{
  if (chain.size < 2)
    return;
  pts.resize(chain.size);  // (a buffer kept between edges and frames)
  for (std::size_t k = 0; k < chain.size; ++k)
    pts[k] = chain[k];
  // Grid order is ring-major, not along the edge; ordering by position on the principal axis
  // gives one clean stroke for both vertical (across rings) and along-ring chains.
  Eigen::Vector3f axis = prim.axis;
  if (!(axis.squaredNorm() > 0.0f) || !axis.allFinite())
    axis = pts.back() - pts.front();
  const Eigen::Vector3f c = prim.centroid;
  std::sort(pts.begin(), pts.end(), [&](const Eigen::Vector3f& p, const Eigen::Vector3f& q) {
    return (p - c).dot(axis) < (q - c).dot(axis);
  });
  auto& line = addMarker(out, header, kEdgeNs, prim, visualization_msgs::Marker::LINE_STRIP);
  line.scale.x = kEdgeLineWidth;
  line.color = colourOf(Label::Edge, 1.0f);
  line.points.reserve(pts.size());
  for (const auto& p : pts)
    line.points.push_back(toPoint(p));
}

void addCluster(const PrimitiveInfo& prim, const Points& pts, const std_msgs::Header& header, const char* ns,
                double diameter, Slots& out)
{
  auto& spheres = addMarker(out, header, ns, prim, visualization_msgs::Marker::SPHERE_LIST);
  spheres.scale.x = spheres.scale.y = spheres.scale.z = diameter;
  spheres.color = colourOf(prim.label, 1.0f);
  spheres.points.reserve(pts.size);
  for (std::size_t k = 0; k < pts.size; ++k)
    spheres.points.push_back(toPoint(pts[k]));
}

}  // namespace

visualization_msgs::MarkerArrayPtr makePrimitiveMarkers(const PrimitiveSet& prims,
                                                        const PointCloudView& cloud,
                                                        const std_msgs::Header& header,
                                                        visualization_msgs::MarkerArrayPtr reuse,
                                                        MarkerScratch* scratch)
{
  MarkerScratch local;
  MarkerScratch& buf = scratch != nullptr ? *scratch : local;
  auto array = recycled(std::move(reuse));
  array->markers.reserve(2 * prims.primitives.size() + 1);
  Slots out{array->markers};
  visualization_msgs::Marker& clear = out.next(header, "");
  clear.action = visualization_msgs::Marker::DELETEALL;

  for (const PrimitiveInfo& prim : prims.primitives)
  {
    if (prim.label == Label::Plane)
    {
      PlaneExtents extents;
      if (!planeFrame(prim, extents.f))
        continue;
      if (pointsOf(prims, prim, cloud, extents) > 0)
      {
        extents.merge();
        addPlane(prim, extents, header, out);
      }
      continue;
    }
    const Points pts = storedPoints(prims, prim, cloud, buf);
    if (pts.size == 0)
      continue;
    switch (prim.label)
    {
      case Label::Plane:  // (above)
        break;
      case Label::Edge:
        addEdge(prim, pts, header, buf.chain, out);
        break;
      case Label::Corner:
        addCluster(prim, pts, header, kCornerNs, kCornerSphere, out);
        break;
      case Label::Rough:
        addCluster(prim, pts, header, kRoughNs, kRoughSphere, out);
        break;
      case Label::None:
        break;
    }
  }
  array->markers.resize(out.used);  // (only ever shrinks: no default markers are added)
  return array;
}

}  // namespace ring_curvature
