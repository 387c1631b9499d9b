// libFuzzer harness: the command line's value parsers. The first byte picks the parser (camera, size, light,
// memory size, a technique parameter, a built-in scene spec), the rest is the text. std::invalid_argument (and
// SceneError for built-in scene specs) is the verdict; anything else a finding.
#include <cstddef>
#include <cstdint>
#include <string>

#include "host/pipeline/memory_plan.h"
#include "host/scene/camera.h"
#include "host/scene/light.h"
#include "host/scene/procedural.h"
#include "host/techniques/technique.h"
#include "tests/fuzz/fuzz_support.h"

namespace {

using namespace penumbra;

// Parameter `index` of technique `index / 64`, set from `text` (every technique's every parameter is reachable).
void setParam(uint8_t index, const std::string& text) {
  const auto& all = techniques();
  const TechniqueInfo& info = all[index % all.size()];
  if (info.params.empty()) return;
  Params params(info.params);
  params.set(info.params[(index / all.size()) % info.params.size()].name, text);
}

void parse(uint8_t which, const std::string& text) {
  int w = 0, h = 0;
  switch (which % 6) {
    case 0:
      parseCamera(text);
      break;
    case 1:
      parseSize(text, w, h);
      break;
    case 2:
      parseLight(text);
      break;
    case 3:
      parseMemorySize(text, "--memory-limit");
      break;
    case 4:
      setParam(static_cast<uint8_t>(which / 6), text);
      break;
    default:
      makeProceduralFromSpec(text);
      break;
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size == 0) return 0;
  const std::string text(reinterpret_cast<const char*>(data) + 1, size - 1);
  fuzz::expectOnly<std::invalid_argument>("fuzz_cli_values", [&] {
    try {
      parse(data[0], text);
    } catch (const SceneError& e) {  // a built-in scene spec's verdict
      throw std::invalid_argument(e.what());
    }
  });
  return 0;
}
