// The technique each light of a frame is shadowed with: the frame's, or a scene file light's own ("technique" and
// "params", host/scene/light.h). Shared by the command line and the library, so a scene renders the same through
// both.
#pragma once

#include <string>
#include <vector>

#include "host/pipeline/renderer.h"
#include "host/scene/scene.h"
#include "host/techniques/technique.h"

namespace penumbra {

// A light without a technique of its own gets `technique` with `params`. A light with one gets that technique's
// defaults, then the values of `inherited` that the technique has (the parameters the caller gave explicitly:
// the command line's, or those set on the library's params), then the light's own "params" on top. Throws
// std::invalid_argument "SOURCE: light L: ..." for an unknown technique, a parameter the light's technique lacks
// or a bad value, before any work.
std::vector<FrameLight> resolveFrameLights(const std::vector<Light>& lights, const TechniqueInfo& technique,
                                           const Params& params, const ParamValues& inherited,
                                           const std::string& source);

}  // namespace penumbra
