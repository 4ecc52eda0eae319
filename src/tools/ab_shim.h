// The plain C interface between ab_core (the in-process A/B timer) and one build of the core.
// ab_core loads two builds of libring_curvature_core.so into two link namespaces (dlmopen); each
// gets a copy of ab_shim.cpp compiled against that build's headers. Only C types cross this
// line, so the two builds' class layouts never have to agree with each other or with ab_core.
#pragma once

#include <stddef.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

/// Raised whenever a struct below or a function's meaning changes: ab_core refuses a shim of
/// another version (an old shim copied next to an old build's library).
#define RC_AB_SHIM_VERSION 1

/// One field of the point records; offset -1 when absent, type numbered like
/// sensor_msgs::PointField (INT8 = 1 ... FLOAT64 = 8).
typedef struct RcAbField
{
  int64_t offset;
  uint8_t type;
} RcAbField;

/// One frame: interleaved little-endian records, as in a sensor_msgs/PointCloud2.
typedef struct RcAbCloud
{
  const uint8_t* data;
  size_t data_size;
  uint32_t width, height, point_step, row_step;
  RcAbField x, y, z, ring, time, intensity;
} RcAbCloud;

/// Stages in the order of ring_curvature::StageTimes.
#define RC_AB_STAGES 6

typedef struct RcAbResult
{
  double stage_ms[RC_AB_STAGES];  ///< the pipeline's own StageTimes of this frame
  uint64_t output_hash;           ///< FNV-1a of every per-point output; 0 unless asked for
  uint64_t primitives;            ///< primitives reported for the frame
} RcAbResult;

int rc_ab_version(void);
/// A pipeline with default parameters; NULL on failure.
void* rc_ab_create(void);
/// Processes one frame. Returns 0 on success; otherwise writes the pipeline's message into
/// err (NUL-terminated, truncated to err_size). want_hash != 0 also fills output_hash.
int rc_ab_process(void* pipeline, const RcAbCloud* cloud, RcAbResult* result, int want_hash, char* err,
                  size_t err_size);
void rc_ab_destroy(void* pipeline);

#ifdef __cplusplus
}
#endif
