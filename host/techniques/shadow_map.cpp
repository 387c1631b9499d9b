// Shadow-map rendering shared by sm, pcf, pcss and the moment-based techniques.
#include "host/techniques/shadow_map.h"

namespace penumbra {

std::vector<ParamSpec> shadowMapParams() {
  return {
      {"map-size", 2048, 16, 8192, "Shadow-map width and height in texels"},
      {"bias", 1.0, 0, 100, "Constant depth bias, in texel footprints at the receiver"},
      {"slope-bias", 1.0, 0, 100, "Slope-scaled depth bias, in texel footprints times tan(angle to the light)"},
      {"normal-offset", 1.0, 0, 100, "Receiver offset along its normal, in texel footprints"},
  };
}

BiasArgs biasArgs(const Params& params) {
  return {static_cast<float>(params.get("bias")), static_cast<float>(params.get("slope-bias")),
          static_cast<float>(params.get("normal-offset"))};
}

void renderShadowMap(ShadowFrame& frame, int size, ShadowMap& map) {
  map.view = fitLightView(frame.light, frame.scene.bounds(), size);
  frame.raster.draw(map.view.raster, map.targets);
  if (map.gpu.empty()) map.gpu.allocate(frame.ctx, 1, CL_MEM_READ_ONLY);
  map.gpu.upload(frame.ctx, std::span<const LightViewGpu>(&map.view.gpu, 1));
}

}  // namespace penumbra
