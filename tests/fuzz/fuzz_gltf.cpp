// libFuzzer harness: one input is one glTF file, JSON (.gltf) or binary (.glb, chosen by its magic), loaded with
// the fuzz limits. A SceneError is the loader's verdict; any other exception, a crash or a sanitizer report is a
// finding.
#include <cstddef>
#include <cstdint>
#include <cstring>

#include "host/scene/gltf_loader.h"
#include "tests/fuzz/fuzz_support.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  using namespace penumbra;
  const bool glb = size >= 4 && std::memcmp(data, "glTF", 4) == 0;
  const std::string path = fuzz::inPlacePath() ? std::string(fuzz::inPlacePath())
                                               : fuzz::writeScratch(glb ? "input.glb" : "input.gltf", data, size);
  fuzz::expectOnly<SceneError>("fuzz_gltf", [&] { loadGltf(path, fuzz::fuzzLimits()); });
  return 0;
}
