// Embree 3, loaded when the first tracer is made (dlopen of libembree3.so.3) rather than linked: the `penumbra` tool
// and the test binaries start, and `penumbra selftest` runs, on a machine without Embree (the GPU machine's pack of
// the tool alone is 9 MB instead of 51), and only `reference` and bench's references need it. The entry points the
// tracer calls, resolved once; the header's inline helpers (rtcInitIntersectContext, RTCHitN_*) need no library.
#pragma once

#include <embree3/rtcore.h>

namespace penumbra::reference {

struct EmbreeApi {
  decltype(&::rtcNewDevice) rtcNewDevice;
  decltype(&::rtcReleaseDevice) rtcReleaseDevice;
  decltype(&::rtcGetDeviceError) rtcGetDeviceError;
  decltype(&::rtcGetDeviceProperty) rtcGetDeviceProperty;
  decltype(&::rtcSetDeviceErrorFunction) rtcSetDeviceErrorFunction;
  decltype(&::rtcNewScene) rtcNewScene;
  decltype(&::rtcReleaseScene) rtcReleaseScene;
  decltype(&::rtcSetSceneFlags) rtcSetSceneFlags;
  decltype(&::rtcSetSceneBuildQuality) rtcSetSceneBuildQuality;
  decltype(&::rtcCommitScene) rtcCommitScene;
  decltype(&::rtcNewGeometry) rtcNewGeometry;
  decltype(&::rtcReleaseGeometry) rtcReleaseGeometry;
  decltype(&::rtcSetNewGeometryBuffer) rtcSetNewGeometryBuffer;
  decltype(&::rtcSetGeometryUserData) rtcSetGeometryUserData;
  decltype(&::rtcSetGeometryOccludedFilterFunction) rtcSetGeometryOccludedFilterFunction;
  decltype(&::rtcSetGeometryIntersectFilterFunction) rtcSetGeometryIntersectFilterFunction;
  decltype(&::rtcCommitGeometry) rtcCommitGeometry;
  decltype(&::rtcAttachGeometry) rtcAttachGeometry;
  decltype(&::rtcOccluded1M) rtcOccluded1M;
  decltype(&::rtcIntersect1) rtcIntersect1;
};

// Loads Embree on first use (thread-safe) and keeps it loaded: PENUMBRA_EMBREE_LIBRARY (a path, or a name the loader
// searches) when set, else libembree3.so.3. Throws std::runtime_error naming the library and the loader's reason when
// it is missing or lacks an entry point.
const EmbreeApi& embree();

}  // namespace penumbra::reference
