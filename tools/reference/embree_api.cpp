#include "tools/reference/embree_api.h"

#include <dlfcn.h>
#include <fmt/format.h>

#include <cstdlib>
#include <iterator>
#include <memory>
#include <mutex>
#include <stdexcept>
#include <string>
#include <vector>

namespace penumbra::reference {
namespace {

// Debian's libembree3-3 (the runtime package of libembree-dev); the unversioned name where only a development link is
// installed.
constexpr const char* kLibraries[] = {"libembree3.so.3", "libembree3.so"};

template <class F>
void resolve(void* library, const char* name, F& function) {
  function = reinterpret_cast<F>(dlsym(library, name));
  if (function == nullptr)
    throw std::runtime_error(fmt::format("reference: the Embree library lacks {} (not Embree 3?)", name));
}

EmbreeApi load() {
  void* library = nullptr;
  std::string reasons;
  std::vector<std::string> names(std::begin(kLibraries), std::end(kLibraries));
  if (const char* chosen = std::getenv("PENUMBRA_EMBREE_LIBRARY"); chosen != nullptr && *chosen != '\0')
    names = {chosen};  // an Embree 3 of the user's own (a path or a name the loader searches)
  for (const std::string& name : names) {
    library = dlopen(name.c_str(), RTLD_NOW | RTLD_LOCAL);
    if (library != nullptr) break;
    const char* why = dlerror();
    reasons += fmt::format("{}{}", reasons.empty() ? "" : "; ", why != nullptr ? std::string(why) : name);
  }
  if (library == nullptr)
    throw std::runtime_error(
        fmt::format("reference: Embree 3 is not installed ({}); the ray-traced reference needs it (Debian: apt install "
                    "libembree3-3)",
                    reasons));
  EmbreeApi api{};
#define PENUMBRA_EMBREE_RESOLVE(name) resolve(library, #name, api.name)
  PENUMBRA_EMBREE_RESOLVE(rtcNewDevice);
  PENUMBRA_EMBREE_RESOLVE(rtcReleaseDevice);
  PENUMBRA_EMBREE_RESOLVE(rtcGetDeviceError);
  PENUMBRA_EMBREE_RESOLVE(rtcGetDeviceProperty);
  PENUMBRA_EMBREE_RESOLVE(rtcSetDeviceErrorFunction);
  PENUMBRA_EMBREE_RESOLVE(rtcNewScene);
  PENUMBRA_EMBREE_RESOLVE(rtcReleaseScene);
  PENUMBRA_EMBREE_RESOLVE(rtcSetSceneFlags);
  PENUMBRA_EMBREE_RESOLVE(rtcSetSceneBuildQuality);
  PENUMBRA_EMBREE_RESOLVE(rtcCommitScene);
  PENUMBRA_EMBREE_RESOLVE(rtcNewGeometry);
  PENUMBRA_EMBREE_RESOLVE(rtcReleaseGeometry);
  PENUMBRA_EMBREE_RESOLVE(rtcSetNewGeometryBuffer);
  PENUMBRA_EMBREE_RESOLVE(rtcSetGeometryUserData);
  PENUMBRA_EMBREE_RESOLVE(rtcSetGeometryOccludedFilterFunction);
  PENUMBRA_EMBREE_RESOLVE(rtcSetGeometryIntersectFilterFunction);
  PENUMBRA_EMBREE_RESOLVE(rtcCommitGeometry);
  PENUMBRA_EMBREE_RESOLVE(rtcAttachGeometry);
  PENUMBRA_EMBREE_RESOLVE(rtcOccluded1M);
  PENUMBRA_EMBREE_RESOLVE(rtcIntersect1);
#undef PENUMBRA_EMBREE_RESOLVE
  return api;
}

}  // namespace

const EmbreeApi& embree() {
  // A failed load is not cached: the next tracer retries (and reports) again.
  static std::mutex mutex;
  static std::unique_ptr<EmbreeApi> api;
  std::lock_guard<std::mutex> lock(mutex);
  if (!api) api = std::make_unique<EmbreeApi>(load());
  return *api;
}

}  // namespace penumbra::reference
