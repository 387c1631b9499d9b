#include "tools/reference/embree_api.h"

#include <dlfcn.h>
#include <fmt/format.h>

#include <cstdlib>
#include <iterator>
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
#define PENUMBRA_EMBREE_RESOLVE(name) resolve(library, #name, api.name);
  PENUMBRA_EMBREE_FUNCTIONS(PENUMBRA_EMBREE_RESOLVE)
#undef PENUMBRA_EMBREE_RESOLVE
  return api;
}

}  // namespace

const EmbreeApi& embree() {
  // A static's initialisation is thread-safe, costs a guard check once done (the tracer calls this per ray and per
  // stream), and is tried again on the next call when it throws: a failed load is reported again, never cached.
  static const EmbreeApi api = load();
  return api;
}

}  // namespace penumbra::reference
