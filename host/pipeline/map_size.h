// `--map-size auto`: the size of a light's map chosen per frame from what the camera's pixels need (Luksch sec. 7,
// eq. 5: one texel per pixel), before the technique is chosen, so that the renderer keeps one technique instance per
// size and a new size is a new instance.
#pragma once

#include <functional>

#include "host/techniques/params.h"
#include "host/techniques/technique.h"
#include "raster/rasterizer.h"

namespace penumbra {

// True when `params` has a map-size of auto (0).
bool autoMapSize(const Params& params);

// Throws std::invalid_argument naming both options when map-size-min is above map-size-max (before any work; it used
// to surface mid-frame as "neededMapSize: ... an empty size range").
void checkMapSizeRange(const Params& params);

// The light's view drawn small (kMapProbeSize^2, one cube face after another) for what only a drawn map tells: how wide
// the shadows' penumbrae are and how thin the casters are. The renderer keeps one per light, so its targets are
// allocated once.
inline constexpr int kMapProbeSize = 512;
struct MapProbe {
  RasterTargets targets;
  Buffer<LightViewGpu> view;
};

// The map size for this frame, the largest of three needs, rounded up to a multiple of 128 texels within
// map-size-min .. map-size-max:
// - the pixels' (neededMapSize over the view the technique fits, the LiSPSM warp included, or a point light's six cube
//   faces with their guard band, probed at 1024 texels): map-size-quantile of the camera's pixels get a texel each;
// - the penumbrae's (area lights, map-size-penumbra > 0): the penumbra half-width that map-size-penumbra-quantile of
//   the shadowed pixels reach spans map-size-penumbra texels (a narrower penumbra is an edge drawn at the texel's
//   resolution; wider ones are filtered, and more texels buy nothing);
// - the casters' (map-size-detail > 0): the thinnest 5 % of the features the probe holds span map-size-detail texels
//   (a pole or a bar narrower than a texel drops out of the map).
// Under an area light the pixels' need (not the other two) is capped where the median penumbra half-width would span
// more than map-size-penumbra-max texels: a penumbra that wide is filtered, and more texels buy nothing. With
// `kernelReach` (TechniqueInfo::kernelReach: the texels the technique clamps its kernels' half-width at, on a map of
// the given size; it may grow with the size, no faster than in proportion) the size, needs and all, is at most the
// largest multiple of 128 where the median penumbra half-width spans no more than that: beyond, half the penumbrae
// would be drawn narrower than they are.
// The last two are measured on `probe`. Records "penumbra:map-size" (the size and each need) in frame.attributes. The
// technique's instance is made with it (TechniqueInfo::create's mapSize).
int sizeMapForFrame(ShadowFrame& frame, const Params& params, MapProbe& probe,
                    const std::function<double(int mapSize)>& kernelReach = {});

}  // namespace penumbra
