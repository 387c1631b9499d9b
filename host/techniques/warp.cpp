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

WarpSettings WarpSettings::from(const Params& params) {
  WarpSettings warp;
  if (!params.has("warp")) return warp;
  warp.declared = true;
  warp.lispsm = params.getInt("warp") == kWarpLispsm;
  warp.n = static_cast<float>(params.get("lispsm-n"));
  return warp;
}

LightView fitWarpedLightView(const ShadowFrame& frame, const WarpSettings& warp, int size, float marginTexels,
                             float nearDepth, float farDepth, const ReceiverBounds* receivers, LispsmFit* fit) {
  if (!warp.lispsm) return fitLightView(frame.light, frame.scene.bounds(), size, receivers, marginTexels);
  if (frame.camera.orthographic()) {  // LiSPSM warps towards the eye point; parallel view rays have none
    if (fit != nullptr) *fit = LispsmFit{}, fit->uniformBecause = kOrthographicFallback;
    return fitLightView(frame.light, frame.scene.bounds(), size, receivers, marginTexels);
  }
  const LispsmInput input{frame.light, frame.camera,         nearDepth,
                          farDepth,    frame.scene.bounds(), receivers,
                          size,        marginTexels,         warp.n};
  return fitLispsmView(input, fit);
}

LightView fitWarpedLightView(ShadowFrame& frame, const WarpedFit& fitted, int size, float marginTexels) {
  const ReceiverBounds* receivers = fitted.fitReceivers ? &frame.receivers : nullptr;
  if (!fitted.warp.lispsm) {
    if (fitted.warp.declared) frame.attributes["penumbra:warp"] = "none";  // techniques without the option: no entry
    return fitLightView(frame.light, frame.scene.bounds(), size, receivers, marginTexels);
  }
  // The camera depth range the map serves: the visible pixels' (as pssm's splits take theirs).
  const auto [near, far] = tightViewDepth(frame.ctx, frame.gbuffer);
  LispsmFit fit;
  LightView view = fitWarpedLightView(frame, fitted.warp, size, marginTexels, near, far, receivers, &fit);
  frame.attributes["penumbra:warp"] = fit.describe();
  return view;
}

}  // namespace penumbra
