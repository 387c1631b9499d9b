// Warp parameters and the warped (or uniform) fit of a technique's light map.
#include "host/techniques/warp.h"

#include "host/views/light_fit.h"

namespace penumbra {
namespace {

enum WarpChoice { kWarpNone = 0, kWarpLispsm = 1 };
constexpr const char* kOrthographicFallback = "orthographic camera (no eye point to warp towards)";

}  // namespace

std::vector<ParamSpec> warpParams(bool lispsmByDefault) {
  return {
      {"warp",
       static_cast<double>(lispsmByDefault ? kWarpLispsm : kWarpNone),
       0,
       1,
       "Light-map parameterisation: uniform, or light-space perspective (LiSPSM; sun or spot light); default none, "
       "jittered: lispsm",
       {"none", "lispsm"}},
      {"lispsm-n", 0.0, 0, 1e6,
       "LiSPSM warp distance n in world units (small: more texels near the camera); 0 = automatic n_opt"},
  };
}

bool lispsmEnabled(const Params& params) { return params.has("warp") && params.getInt("warp") == kWarpLispsm; }

LightView fitWarpedLightView(const ShadowFrame& frame, const Params& params, int size, float marginTexels,
                             float nearDepth, float farDepth, const ReceiverBounds* receivers, LispsmFit* fit) {
  if (!lispsmEnabled(params)) return fitLightView(frame.light, frame.scene.bounds(), size, receivers, marginTexels);
  if (frame.camera.orthographic()) {  // LiSPSM warps towards the eye point; parallel view rays have none
    if (fit != nullptr) *fit = LispsmFit{}, fit->uniformBecause = kOrthographicFallback;
    return fitLightView(frame.light, frame.scene.bounds(), size, receivers, marginTexels);
  }
  const LispsmInput input{frame.light, frame.camera,         nearDepth,
                          farDepth,    frame.scene.bounds(), receivers,
                          size,        marginTexels,         static_cast<float>(params.get("lispsm-n"))};
  return fitLispsmView(input, fit);
}

LightView fitWarpedLightView(ShadowFrame& frame, const Params& params, int size, float marginTexels) {
  const ReceiverBounds* receivers = params.getInt("fit") == 1 ? &frame.receivers : nullptr;
  if (!lispsmEnabled(params)) {
    if (params.has("warp")) frame.attributes["penumbra:warp"] = "none";  // techniques without the option: no entry
    return fitLightView(frame.light, frame.scene.bounds(), size, receivers, marginTexels);
  }
  // The camera depth range the map serves: the visible pixels' (as pssm's splits take theirs).
  const auto [near, far] = tightViewDepth(frame.ctx, frame.gbuffer);
  LispsmFit fit;
  LightView view = fitWarpedLightView(frame, params, size, marginTexels, near, far, receivers, &fit);
  frame.attributes["penumbra:warp"] = fit.describe();
  return view;
}

}  // namespace penumbra
