// One build's side of ab_core: ring_curvature::Pipeline behind the C interface of ab_shim.h.
// Compiled once per build against that build's own headers (src/tools/ab_core.sh does it for a
// build that lacks libring_curvature_ab_shim.so), so the Pipeline and FrameResult it allocates
// have that build's layout, whatever the other build's is.
#include "ab_shim.h"
#include "fnv_hash.hpp"

#include <algorithm>
#include <cstring>
#include <exception>
#include <string>
#include <vector>

#include "ring_curvature/pipeline.hpp"

namespace rc = ring_curvature;

namespace
{

// Owned together: the result's buffers are reused frame after frame, as in the nodelet, so
// that the timed call allocates nothing once warm.
struct Session
{
  rc::Pipeline pipeline;
  rc::FrameResult result;
};

rc::FieldView toField(const RcAbField& f)
{
  rc::FieldView v;
  v.offset = f.offset;
  v.type = static_cast<rc::ScalarType>(f.type);
  return v;
}

std::uint64_t outputHash(const rc::FrameResult& r)
{
  std::uint64_t h = rc::bench::kFnvOffsetBasis;
  rc::bench::hashVector(h, r.label);
  rc::bench::hashVector(h, r.curvature);
  rc::bench::hashVector(h, r.smoothness);
  rc::bench::hashVector(h, r.discontinuity);
  rc::bench::hashVector(h, r.primitive);
  const std::uint64_t n = r.primitives.primitives.size();
  rc::bench::hashBytes(h, &n, sizeof n);
  // every field of every primitive, one by one (a struct's padding bytes are not its value)
  for (const rc::PrimitiveInfo& p : r.primitives.primitives)
  {
    rc::bench::hashBytes(h, &p.id, sizeof p.id);
    rc::bench::hashBytes(h, &p.label, sizeof p.label);
    rc::bench::hashBytes(h, &p.num_points, sizeof p.num_points);
    rc::bench::hashBytes(h, &p.first, sizeof p.first);
    for (const Eigen::Vector3f* v : {&p.centroid, &p.axis, &p.eigenvalues, &p.bbox_min, &p.bbox_max})
      rc::bench::hashBytes(h, v->data(), 3 * sizeof(float));
    rc::bench::hashBytes(h, &p.rms_error, sizeof p.rms_error);
    rc::bench::hashBytes(h, &p.ring_min, sizeof p.ring_min);
    rc::bench::hashBytes(h, &p.ring_max, sizeof p.ring_max);
  }
  rc::bench::hashVector(h, r.primitives.indices);
  rc::bench::hashVector(h, r.primitives.of_grid);
  return h;
}

}  // namespace

extern "C" {

int rc_ab_version(void) { return RC_AB_SHIM_VERSION; }

// Nothing may unwind across the C interface (ab_core runs another copy of libstdc++, in another
// link namespace): failures become return values.
void* rc_ab_create(void)
{
  try
  {
    return new Session();
  }
  catch (...)
  {
    return nullptr;
  }
}

int rc_ab_process(void* pipeline, const RcAbCloud* cloud, RcAbResult* result, int want_hash, char* err,
                  size_t err_size)
{
  auto* s = static_cast<Session*>(pipeline);
  rc::PointCloudView v;
  v.data = cloud->data;
  v.data_size = cloud->data_size;
  v.width = cloud->width;
  v.height = cloud->height;
  v.point_step = cloud->point_step;
  v.row_step = cloud->row_step;
  v.x = toField(cloud->x);
  v.y = toField(cloud->y);
  v.z = toField(cloud->z);
  v.ring = toField(cloud->ring);
  v.time = toField(cloud->time);
  v.intensity = toField(cloud->intensity);

  rc::Status st;
  try
  {
    st = s->pipeline.process(v, s->result);
  }
  catch (const std::exception& e)
  {
    st = rc::Status::error(std::string("exception: ") + e.what());
  }
  if (!st)
  {
    if (err && err_size > 0)
    {
      const std::size_t n = std::min(err_size - 1, st.message.size());
      std::memcpy(err, st.message.data(), n);
      err[n] = '\0';
    }
    return 1;
  }
  const rc::StageTimes& t = s->result.times;
  const double stages[RC_AB_STAGES] = {t.grid, t.features, t.thresholds, t.classification, t.primitives, t.output};
  std::copy(stages, stages + RC_AB_STAGES, result->stage_ms);
  result->primitives = s->result.primitives.primitives.size();
  result->output_hash = want_hash ? outputHash(s->result) : 0;
  return 0;
}

void rc_ab_destroy(void* pipeline) { delete static_cast<Session*>(pipeline); }

}  // extern "C"
