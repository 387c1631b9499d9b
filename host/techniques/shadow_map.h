// The single shadow map most techniques start from: the light's view fitted to the visible receivers and
// their casters, its linear depth rasterized by our rasterizer, and the shared bias parameters.
#pragma once

#include <functional>
#include <string>
#include <vector>

#include "host/cl/kernel.h"
#include "host/techniques/params.h"
#include "host/techniques/technique.h"
#include "host/techniques/warp.h"
#include "host/views/views.h"
#include "kernels/shared/shade.h"

namespace penumbra {

// Work-group size of the per-pixel kernels: 64 work-items (two NVIDIA warps, one AMD wavefront), 32 on CPU devices.
// PoCL's pthread device deals its threads runs of up to 256 groups per thread (512 on two), so with 64 pixels a group
// a run is a seventh of a 640x360 frame, and the thread that draws the run holding the shadows (the costly pixels)
// works on alone at the end; halving the group halves the runs (docs/performance.md, "Work spread over a CPU's
// threads").
inline size_t pixelGroup(const Context& ctx) { return ctx.info().isCpu() ? 32 : 64; }
// Bandwidth floor of a per-pixel visibility kernel (Kernel::moves): read the pixel's position and normal (two
// float4), write its visibility (a float). Map reads depend on the filter and caches; debug outputs are optional.
inline constexpr uint64_t kVisibilityBytesPerPixel = 2 * 16 + 4;

struct ShadowMap {
  LightView view;
  RasterTargets targets;     // depth: linear light depth, +INFINITY where empty
  Buffer<LightViewGpu> gpu;  // view.gpu on the device (one element) for __constant arguments
  bool triangleIds = false;  // renderShadowMap draws targets.triangleId too (an ID buffer reads them)
  // renderShadowMap leaves out the triangles that can shadow no point of the scene (RasterView::casterLight): for
  // techniques that only compare depths with the map's texels (sm, pcf, pcss, jittered), never for filtered moments.
  bool castersOnly = false;
  // renderShadowMap draws every triangle and records the tiles no caster reaches (RasterView::recordCasterTiles,
  // targets.casterFreeTiles): for maps of filtered moments, which keep their receivers, whose min-max pyramid holds the
  // casters alone (vssm's HSM).
  bool casterTiles = false;
  // With casterTiles, given the fitted view: >= 0 draws the receivers only within that many texels of the casters'
  // box, the tiles no caster reaches beyond it left as the background (RasterView::receiverReach), for maps whose
  // filtered texels are read only around their casters (vssm's window); -1 (or none) draws every tile.
  std::function<int(const LightViewGpu&)> receiverReach;
};

// map-size (auto: chosen per frame by the renderer from the camera's pixels, host/views/light_fit.h neededMapSize),
// map-size-quantile, -min, -max, fit, bias, slope-bias, normal-offset, cube-guard (point lights:
// host/pipeline/point_light.h).
std::vector<ParamSpec> shadowMapParams();
// For the techniques whose kernels move the receiver by the whole normal offset at every angle (sm, fvsm, jittered:
// SHADOW_NORMAL_OFFSET_SCALED 0 in kernels/shared/shadow_common.h): normal-offset's help says so.
void unscaledNormalOffset(std::vector<ParamSpec>& params);
// For a technique that traces no penumbra wider than a few texels (sm draws hard edges; pcf's kernel reaches
// --pcf-radius-max, 4 texels): --map-size auto's penumbra need asks for 3 texels across a penumbra's half-width instead
// of a filter's 6 (its edge is placed within a third of the half-width, and more texels only widen the penumbra beyond
// what it draws), and caps the pixels' need where the median half-width would span 4 texels instead of 16.
void shortPenumbraMapSize(std::vector<ParamSpec>& params);
// For a technique that blurs its moments with one radius per frame (vsm, evsm4, msm, lvsm; savsm's SAT): --map-size
// auto's penumbra need is read at the narrowest fifth of the shadowed pixels instead of the narrowest tenth. Such a map
// draws every penumbra with one kernel, so the narrowest tenth (contact lines, where the bias decides) buys it little:
// on scenes/default.json at 640x360 it drew 3840^2 for MAE 3-4 % below the fifth's ~1900^2 at 2.2-6x the time, while
// builtin:cards (alpha holes: every penumbra narrow) and builtin:staircase draw the same size either way
// (docs/techniques/moments.md, "Map size").
void blurredPenumbraMapSize(std::vector<ParamSpec>& params);
// For split techniques (pssm, psvsm): --map-size auto sizes every split's map as one map of the light's whole view
// (the family's needs, set before this call), at most --map-size-max, whose default here is the former fixed 2048.
void splitMapSize(std::vector<ParamSpec>& params);
// For techniques whose map-size is not one uniform map's (per split, or warped): no auto and its settings; `why`
// goes into the help.
void fixMapSize(std::vector<ParamSpec>& params, const std::string& why);

// shadowMapParams() as parsed: what renderShadowMap and the shading kernels read. The auto-size settings
// (map-size-quantile, -min, -max) and cube-guard are the renderer's (host/pipeline/map_size.h, point_light.h), not
// the instance's.
struct MapSettings {
  int size = 0;  // texels per side: --map-size, or the frame's choice under auto
  WarpedFit fit;  // --fit receivers|scene and the warp (host/techniques/warp.h)
  float bias = 0, slopeBias = 0, normalOffset = 0;
  // Throws std::logic_error when --map-size is auto and `autoSize` (the frame's choice) is not positive.
  static MapSettings from(const Params& params, int autoSize);
  ReceiverBias receiverBias() const { return {bias, slopeBias, normalOffset}; }
  bool operator==(const MapSettings&) const = default;
};

// Whether a technique reads the map's near depth (lv->zNear): moment normalisation and blocker searches start there
// (Drawn: tightened to the nearest caster drawn, a reduction over every texel); depth comparisons alone do not
// (Fitted: the fit's near plane kept, no pass over the map).
enum class MapNear { Drawn, Fitted };

// Fits the light's view (per --fit: the whole scene, or the visible receivers with a margin around them of
// `reachTexels`, the farthest any of the technique's taps reaches from a receiver's texel, plus the normal offset and
// one texel for bilinear taps), rasterizes it, and with MapNear::Drawn tightens view.gpu.zNear to the nearest caster
// actually drawn, so depth ranges (moment normalisation, blocker search) start where the occluders do. With the
// caller's map (frame.callerMap) its view and texels instead of the fit and the draw; zNear is tightened the same way.
void renderShadowMap(ShadowFrame& frame, const MapSettings& settings, ShadowMap& map, float reachTexels,
                     MapNear near = MapNear::Drawn);
// MapNear::Drawn's tightening after the fact, from a minimum a technique drawn with MapNear::Fitted computes anyway
// (the top of its min-max pyramid, computeMinMaxLevels): zNear becomes `drawnMin` where that lies inside the fit's
// range, and the view is published again (header attribute, device copy).
void tightenMapNear(ShadowFrame& frame, const MapSettings& settings, ShadowMap& map, float drawnMin);

// A fixed kernel's half-width chosen per frame from the scene's penumbrae (pcf-radius, blur-radius): NAME (default
// auto, else 0..max texels; `help` says what r is), NAME-quantile (0.05) and NAME-max (`maxDefault`; `maxNote` is
// appended to its help). Under auto the map is fitted with NAME-max's reach (AutoRadius::limit: it is drawn before it
// is measured), then resolveAutoRadius measures the half-width h the quantile of the camera's pixels in the hard
// shadow of its nearest texels reach (host/views/light_fit.h measurePenumbraWidth) and takes r = floor(h) up to
// NAME-max: a box of 2r + 1 taps turns a hard edge into a ramp about as wide as that penumbra. Measured in
// docs/techniques/moments.md and docs/techniques/sm-pcf-pcss.md.
std::vector<ParamSpec> autoRadiusParams(const std::string& name, const std::string& help, double max, double maxDefault,
                                        const std::string& maxNote = {});

// autoRadiusParams(name) as parsed.
struct AutoRadius {
  std::string name;  // "pcf-radius": the header's "penumbra:NAME"
  bool automatic = false;
  int radius = 0;  // texels, when not automatic
  double quantile = 0;
  int max = 0;
  static AutoRadius from(const Params& params, const std::string& name);
  int limit() const { return automatic ? max : radius; }  // the most it can be: the map's margin before it is measured
  bool operator==(const AutoRadius&) const = default;
};

// A filter's widest reach in texels (pcss-max-radius, pcf-max-radius): a count, or under auto (the default) a
// `divisor`-th of the map's side and at least `minimum` texels, the same width in the scene at every size from
// divisor * minimum up, so that a finer map never reaches less far (its penumbrae span more texels). The map is fitted
// with this reach as its margin, before anything is measured on it.
struct AutoReach {
  int divisor = 1;
  int minimum = 0;
  // The parameter: a count of `min` .. `max` texels, or auto (its value min - 1), the default.
  ParamSpec param(const std::string& name, int min, int max, const std::string& help) const;
  float texels(const Params& params, const std::string& name, int mapSize) const;
};

// pcf-radius as autoRadiusParams (auto, at most 4 by default) for pcf and pssm.
std::vector<ParamSpec> pcfRadiusParams();
// pcf-max-radius (pcf, pssm): the auto kernel's widest half-width, by default a 64th of the map's side and at least 16
// texels (a fixed 16 let staircase's penumbrae, 28 texels wide at the narrow end at 4096^2, outgrow the kernel:
// docs/techniques/sm-pcf-pcss.md).
inline constexpr AutoReach kPcfMaxRadius{64, 16};

// A setting chosen per frame from the penumbrae: `choose` of the penumbra half-width (texels of `depth`) that
// `quantile` of the camera's shadowed pixels reach (host/views/light_fit.h measurePenumbraWidth; 0 when none is
// measured), recorded with the measurement in the header's "penumbra:NAME".
int chooseFromPenumbra(ShadowFrame& frame, const Buffer<float>& depth, const Buffer<LightViewGpu>& view,
                       const ReceiverBias& bias, double quantile, const std::string& name,
                       const std::function<int(double halfWidth)>& choose);

// The half-width for this frame: the fixed radius, or under auto measured on `depth` / `view` with `bias` and recorded
// in the header's "penumbra:NAME" (a point light's cube faces each measure their own: host/pipeline/point_light.cpp
// merges them per face). Split techniques measure on split 0's map: their radii are texels of split 0.
int resolveAutoRadius(ShadowFrame& frame, const Buffer<float>& depth, const Buffer<LightViewGpu>& view,
                      const ReceiverBias& bias, const AutoRadius& radius);
inline int resolveAutoRadius(ShadowFrame& frame, const ShadowMap& map, const MapSettings& settings,
                             const AutoRadius& radius) {
  return resolveAutoRadius(frame, map.targets.depth, map.gpu, settings.receiverBias(), radius);
}

// A PCF kernel under --pcf-radius auto (pcf, pssm): its half-width follows the penumbra, floor(h) up to `maxWidth`
// texels, while its taps' radius stops at pcf-radius-max, so a wider kernel spreads its (2 radius + 1)^2 taps and a
// larger map never narrows the kernel in the world. A fixed radius is its own width. Records "penumbra:pcf-radius" and
// "penumbra:pcf-width".
struct AutoKernel {
  int radius = 0;      // taps a side: (2 radius + 1)^2
  float width = 0.0f;  // texels
};
AutoKernel resolveAutoKernel(ShadowFrame& frame, const Buffer<float>& depth, const Buffer<LightViewGpu>& view,
                             const ReceiverBias& bias, const AutoRadius& radius, float maxWidth);

// "receiver-plane": receiver-plane depth bias on (1) or off (0), for the techniques whose kernels take it.
ParamSpec receiverPlaneParam();

// "exact-edges": on (1) or off (0): a hard lookup whose nearest texels disagree is decided by the receiver's exact
// shadow ray against the triangles they hold (kernels/shared/exact_edges.h), for the techniques whose kernels take it
// (fvsm, jittered).
ParamSpec exactEdgesParam();

// pcss-search and vssm-search: the blocker search over the light's cone cut at the near plane (full), or narrowed by
// the nearest caster in it from a min-max pyramid (adaptive, the default).
inline constexpr int kSearchAdaptive = 1;  // their index of "adaptive" ("full" is 0)

// "id-buffer": off | object | polygon | combined (Luksch sec. 9.1; kernels/shared/id_buffer.h), for the techniques
// whose kernels take it (sm, pcf, pssm, jittered).
ParamSpec idBufferParam();

// The scalars every visibility launch of the shadow-map family has (kernels/shared/shade.h): the G-buffer's size,
// the bias of `settings`, the receiver plane (0/1) and the ID buffer's mode (ID_BUFFER_*).
ShadeFrame shadeFrame(const ShadowFrame& frame, const MapSettings& settings, int receiverPlane, int idMode);

// Launches a per-pixel visibility kernel of the shadow-map family (sm, pcf, pcss). Every such kernel takes
// (position, normal, map, light view, ShadeFrame, EXTRA..., visibility): its own scalars travel in a struct of
// kernels/shared/shade.h among EXTRA.
template <class... Extra>
void launchVisibility(ShadowFrame& frame, const ShadowMap& map, const ShadeFrame& shade, const std::string& source,
                      const std::string& entry, Buffer<float>& visibility, const Extra&... extra) {
  const GBuffer& g = frame.gbuffer;
  const uint32_t width = shade.width, height = shade.height;
  Kernel kernel(frame.ctx, source, entry, "shade");
  kernel.args(g.position, g.normal, map.targets.depth, map.gpu, shade, extra..., visibility)
      .moves(uint64_t{width} * height * kVisibilityBytesPerPixel)
      .launch(static_cast<size_t>(width) * height, pixelGroup(frame.ctx));
}

}  // namespace penumbra
