#include "host/pipeline/frame_lights.h"

#include <fmt/format.h>

#include <stdexcept>

namespace penumbra {
namespace {

FrameLight ownTechnique(const Light& light, const ParamValues& inherited) {
  const TechniqueInfo& own = findTechnique(light.technique);
  Params params = techniqueParams(own, inherited, false);
  for (const auto& [name, value] : light.params) {
    if (!own.hasParam(name))
      throw std::invalid_argument(fmt::format("params: \"{}\" is not a parameter of technique '{}'", name, own.name));
    params.set(name, value);
  }
  return {light, &own, std::move(params)};
}

}  // namespace

std::vector<FrameLight> resolveFrameLights(const std::vector<Light>& lights, const TechniqueInfo& technique,
                                           const Params& params, const ParamValues& inherited,
                                           const std::string& source) {
  std::vector<FrameLight> out;
  out.reserve(lights.size());
  for (const Light& light : lights) {
    if (light.technique.empty()) {
      out.push_back({light, &technique, params});
      continue;
    }
    try {
      out.push_back(ownTechnique(light, inherited));
    } catch (const std::invalid_argument& e) {
      throw std::invalid_argument(fmt::format("{}: light {}: {}", source, light.label(), e.what()));
    }
  }
  return out;
}

}  // namespace penumbra
