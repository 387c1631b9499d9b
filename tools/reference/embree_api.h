// Embree 3, loaded when the first tracer is made (dlopen of libembree3.so.3) rather than linked: the `penumbra` tool
// and the test binaries start, and `penumbra selftest` runs, on a machine without Embree (the GPU machine's pack of
// the tool alone is 9 MB instead of 51), and only `reference` and bench's references need it. The entry points the
// tracer calls, resolved once; the header's inline helpers (rtcInitIntersectContext, RTCHitN_*) need no library.
#pragma once

#include <embree3/rtcore.h>

namespace penumbra::reference {

// The entry points, listed once: the struct's members and the loader's lookups both expand this list, so none can be
// left unresolved.
// clang-format off
#define PENUMBRA_EMBREE_FUNCTIONS(X) \
  X(rtcNewDevice) \
  X(rtcReleaseDevice) \
  X(rtcGetDeviceError) \
  X(rtcGetDeviceProperty) \
  X(rtcSetDeviceErrorFunction) \
  X(rtcNewScene) \
  X(rtcReleaseScene) \
  X(rtcSetSceneFlags) \
  X(rtcSetSceneBuildQuality) \
  X(rtcCommitScene) \
  X(rtcNewGeometry) \
  X(rtcReleaseGeometry) \
  X(rtcSetNewGeometryBuffer) \
  X(rtcSetGeometryUserData) \
  X(rtcSetGeometryOccludedFilterFunction) \
  X(rtcSetGeometryIntersectFilterFunction) \
  X(rtcCommitGeometry) \
  X(rtcAttachGeometry) \
  X(rtcOccluded1M) \
  X(rtcIntersect1)
// clang-format on

struct EmbreeApi {
#define PENUMBRA_EMBREE_MEMBER(name) decltype(&::name) name;
  PENUMBRA_EMBREE_FUNCTIONS(PENUMBRA_EMBREE_MEMBER)
#undef PENUMBRA_EMBREE_MEMBER
};

// Loads Embree on first use (thread-safe; a failed load is tried again on the next call) and keeps it loaded:
// PENUMBRA_EMBREE_LIBRARY (a path, or a name the loader searches) when set, else libembree3.so.3. Throws
// std::runtime_error naming the library and the loader's reason when it is missing or lacks an entry point.
const EmbreeApi& embree();

}  // namespace penumbra::reference
