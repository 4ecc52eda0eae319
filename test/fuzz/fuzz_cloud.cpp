// libFuzzer target: arbitrary cloud headers, field layouts and point bytes (see fuzz_input.hpp)
// through (1) the core alone, with a PointCloudView built straight from the fuzz header so that
// the core's own validation is what stands between the bytes and the reads, and (2) the ROS
// input adapter plus everything the nodelet runs per frame (FrameProcessor: makeView, pipeline,
// every output message). ASan/UBSan catch bad reads and UB; the checks below catch results that
// are inconsistent, and any accepted frame must give the same result when processed twice.
#include <cmath>
#include <cstdio>
#include <cstdlib>

#include "fuzz_input.hpp"
#include "fuzz_checks.hpp"
#include "ring_curvature/pipeline.hpp"

namespace rc = ring_curvature;

void ring_curvature::fuzz::require(bool ok, const char* what)
{
  if (ok)
    return;
  std::fprintf(stderr, "fuzz invariant violated: %s\n", what);
  std::abort();
}

using ring_curvature::fuzz::require;

namespace
{

rc::PointCloudView coreView(const rc::fuzz::Input& in)
{
  rc::PointCloudView v;
  v.data = in.data.empty() ? nullptr : in.data.data();
  v.data_size = in.data.size();
  v.width = in.width;
  v.height = in.height;
  v.point_step = in.point_step;
  v.row_step = in.row_step;
  for (const auto& f : in.fields)
  {
    if (f.datatype < 1 || f.datatype > 8)
      continue;
    rc::FieldView fv;
    fv.offset = f.offset;
    fv.type = static_cast<rc::ScalarType>(f.datatype);
    rc::FieldView* slot = f.name == "x"           ? &v.x
                          : f.name == "y"         ? &v.y
                          : f.name == "z"         ? &v.z
                          : f.name == "ring"      ? &v.ring
                          : f.name == "time"      ? &v.time
                          : f.name == "intensity" ? &v.intensity
                                                  : nullptr;
    if (slot && !slot->present())
      *slot = fv;
  }
  return v;
}

}  // namespace

void ring_curvature::fuzz::checkResult(const FrameResult& r, std::size_t n)
{
  require(r.label.size() == n && r.curvature.size() == n && r.smoothness.size() == n &&
              r.discontinuity.size() == n && r.primitive.size() == n,
          "per-point arrays sized like the input");
  std::size_t counted = 0;
  for (std::size_t c : r.label_counts)
    counted += c;
  require(counted == n, "label counts add up to the number of points");
  const auto& prims = r.primitives.primitives;
  for (std::size_t id = 0; id < prims.size(); ++id)
  {
    const rc::PrimitiveInfo& p = prims[id];
    require(p.id == id, "primitive id is its index");
    require(static_cast<std::size_t>(p.first) + p.num_points <= r.primitives.indices.size(),
            "primitive indices in range");
    for (std::uint32_t j = 0; j < p.num_points; ++j)
    {
      const std::uint32_t idx = r.primitives.indices[p.first + j];
      require(idx < n, "primitive point index < n");
      require(r.primitive[idx] == static_cast<std::int32_t>(id), "point carries its primitive id");
      require(r.label[idx] == static_cast<std::uint8_t>(p.label), "point carries its primitive label");
    }
  }
  for (std::size_t i = 0; i < n; ++i)
  {
    require(r.label[i] < rc::kNumLabels, "label in range");
    require(r.primitive[i] < static_cast<std::int32_t>(prims.size()), "primitive index in range");
  }
}

namespace
{

bool same(const std::vector<float>& a, const std::vector<float>& b)
{
  if (a.size() != b.size())
    return false;
  for (std::size_t i = 0; i < a.size(); ++i)
    if (!(a[i] == b[i] || (std::isnan(a[i]) && std::isnan(b[i]))))
      return false;
  return true;
}

void fuzzCore(const rc::fuzz::Input& in, const rc::Params& params)
{
  const rc::PointCloudView view = coreView(in);
  rc::Pipeline pipeline(params);
  rc::FrameResult first, second;
  const rc::Status st = pipeline.process(view, first);
  if (!st)
  {
    require(!st.message.empty(), "a rejection names its problem");
    require(first.label.empty() && first.primitives.primitives.empty(), "a rejected frame has no result");
    return;
  }
  rc::fuzz::checkResult(first, view.size());
  // warm buffers must not change the answer
  require(pipeline.process(view, second).ok, "the same frame accepted twice");
  require(first.label == second.label && same(first.curvature, second.curvature) &&
              first.primitive == second.primitive,
          "same frame, same result");
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size)
{
  rc::fuzz::Input in;
  if (!rc::fuzz::decode(data, size, in))
    return 0;
  const rc::Params params = rc::fuzz::params(in);
  require(params.validate().ok, "fuzz parameters are valid");
  fuzzCore(in, params);
  rc::fuzz::fuzzAdapter(in, params);
  return 0;
}
