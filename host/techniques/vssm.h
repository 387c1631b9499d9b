// `vssm` pieces the tests and benchmarks share with the technique: its parameters and how they become the map
// configuration and the shading kernel's VssmParams.
#pragma once

#include <vector>

#include "host/techniques/params.h"
#include "host/techniques/vssm_maps.h"
#include "kernels/shared/vssm.h"

namespace penumbra {

// vssm-subdivision, vssm-m, vssm-n, vssm-levels, vssm-leaf-taps, vssm-lit-threshold, vssm-contact,
// vssm-max-radius, vssm-min-variance, vssm-sat (the shadow-map parameters come on top).
std::vector<ParamSpec> vssmParamSpecs();
VssmMapConfig vssmMapConfig(const Params& params);
// The kernel's parameters for maps built by `maps`; thresholds scale with the scene's bounding-sphere radius.
VssmParams vssmParams(const Params& params, const VssmMaps& maps, float sceneRadius);

}  // namespace penumbra
