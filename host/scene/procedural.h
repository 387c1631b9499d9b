// Built-in scenes for tests and the demo, each with a default camera and a soft-shadowing light:
// box, stacked-planes, poles, staircase, single-triangle, plane, cards (alpha-tested).
#pragma once

#include <cstdint>
#include <functional>
#include <map>
#include <string>
#include <string_view>
#include <vector>

#include "host/scene/load_options.h"
#include "host/scene/scene.h"

namespace penumbra {

using ProceduralParams = std::map<std::string, double, std::less<>>;

struct ProceduralParam {
  std::string name;
  double defaultValue, min, max;  // inclusive range
  bool integer;
  std::string help;
};

struct ProceduralInfo {
  std::string name;
  std::string description;
  std::vector<ProceduralParam> params;
};

// Every built-in scene with its parameters, in a stable order.
const std::vector<ProceduralInfo>& proceduralScenes();

// Builds a built-in scene. Throws SceneError naming the scene and parameter for an unknown name or
// parameter, a value outside its range, or a fractional value for an integer parameter.
Scene makeProcedural(std::string_view name, const ProceduralParams& params = {});

// The triangles makeProcedural(name, params) would make, without making the large ones (poles: 12 a pole and the
// ground's 2): what a scene file checks against LoadOptions::maxTriangles before building any geometry. Throws as
// makeProcedural does for a bad name or parameter.
uint64_t proceduralTriangleCount(std::string_view name, const ProceduralParams& params = {});

// "NAME" or "NAME:key=value,key=value" (what follows "builtin:" in a scene spec).
Scene makeProceduralFromSpec(std::string_view spec);

}  // namespace penumbra
