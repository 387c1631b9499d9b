// `--map-size auto`: the size of a light's map chosen per frame from what the camera's pixels need (Luksch sec. 7,
// eq. 5: one texel per pixel), before the technique is chosen, so that the renderer keeps one technique instance per
// size and a new size is a new instance.
#pragma once

#include "host/techniques/params.h"
#include "host/techniques/technique.h"

namespace penumbra {

// True when `params` has a map-size of auto (0).
bool autoMapSize(const Params& params);

// Throws std::invalid_argument naming both options when map-size-min is above map-size-max (before any work; it used
// to surface mid-frame as "neededMapSize: ... an empty size range").
void checkMapSizeRange(const Params& params);

// The map size for this frame: neededMapSize over the view the technique fits (fitWarpedLightView, the LiSPSM warp
// included; a point light's six cube faces, their guard band included), probed at 1024 texels, with
// map-size-quantile, -min and -max; records "penumbra:map-size" (the size, the quantile and what it needed) in
// frame.attributes. The technique's instance is made with it (TechniqueInfo::create's mapSize).
int sizeMapForFrame(ShadowFrame& frame, const Params& params);

}  // namespace penumbra
