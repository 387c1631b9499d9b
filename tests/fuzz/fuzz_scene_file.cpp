// libFuzzer harness: one input is one .json scene file, loaded beside a small glTF triangle (triangle.gltf, its
// buffer a data URI) that the input may place as a model. SceneError is the verdict; anything else a finding.
#include <cstddef>
#include <cstdint>
#include <fstream>

#include "host/scene/scene_file.h"
#include "tests/fuzz/fuzz_support.h"

namespace {

// One triangle in the plane z = 0: positions only, as a base64 data URI (36 bytes).
constexpr const char* kTriangle =
    R"({"asset":{"version":"2.0"},"scene":0,"scenes":[{"nodes":[0]}],"nodes":[{"mesh":0}],)"
    R"("meshes":[{"primitives":[{"attributes":{"POSITION":0}}]}],)"
    R"("buffers":[{"byteLength":36,"uri":"data:application/octet-stream;base64,)"
    R"(AAAAAAAAAAAAAAAAAACAPwAAAAAAAAAAAAAAAAAAgD8AAAAA"}],)"
    R"("bufferViews":[{"buffer":0,"byteLength":36}],)"
    R"("accessors":[{"bufferView":0,"componentType":5126,"count":3,"type":"VEC3","min":[0,0,0],"max":[1,1,0]}]})";

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  using namespace penumbra;
  static const bool ready = [] {
    std::ofstream(fuzz::scratch() / "triangle.gltf") << kTriangle;
    return true;
  }();
  (void)ready;
  const std::string path = fuzz::writeScratch("input.json", data, size);
  fuzz::expectOnly<SceneError>("fuzz_scene_file", [&] { loadSceneFile(path, fuzz::fuzzLimits()); });
  return 0;
}
