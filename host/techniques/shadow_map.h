// The single shadow map most techniques start from: the light's view fitted to the scene, its linear
// depth rasterized by our rasterizer, and the shared bias parameters.
#pragma once

#include <vector>

#include "host/pipeline/views.h"
#include "host/techniques/params.h"
#include "host/techniques/technique.h"

namespace penumbra {

struct ShadowMap {
  LightView view;
  RasterTargets targets;       // depth: linear light depth, +INFINITY where empty
  Buffer<LightViewGpu> gpu;    // view.gpu on the device (one element) for __constant arguments
};

// map-size, bias, slope-bias, normal-offset.
std::vector<ParamSpec> shadowMapParams();
void renderShadowMap(ShadowFrame& frame, int size, ShadowMap& map);

// The three bias parameters as kernel arguments, in sc_receiver's order.
struct BiasArgs {
  float constant, slope, normalOffset;
};
BiasArgs biasArgs(const Params& params);

}  // namespace penumbra
