// Shared by the fuzz target's two translation units: one drives the core alone, the other the
// ROS adapter and the output messages.
#pragma once

#include <cstddef>

#include "fuzz_input.hpp"

namespace ring_curvature
{
struct FrameResult;

namespace fuzz
{

/// Aborts (a crash libFuzzer records, with its input) when `ok` is false.
void require(bool ok, const char* what);
/// Per-point arrays sized n, label counts summing to n, primitives consistent with the points.
void checkResult(const FrameResult& r, std::size_t n);
/// The input as a PointCloud2 through FrameProcessor (adapter, pipeline, every output message).
void fuzzAdapter(const Input& in, const Params& params);

}  // namespace fuzz
}  // namespace ring_curvature
