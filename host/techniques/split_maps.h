// The parallel splits shared by pssm and psvsm: parameters, the plan (split distances by scheme or Luksch's
// automatic tiling, one light view per split cropped to its frustum slice), the per-split shadow maps drawn into
// one atlas buffer, the per-pixel AOVs (split index, resolution error) and the provenance in the EXR header.
#pragma once

#include <string>
#include <vector>

#include "host/cl/buffer.h"
#include "host/cl/buffer_copy.h"
#include "host/views/splits.h"
#include "host/techniques/shadow_map.h"
#include "host/techniques/warp.h"
#include "kernels/shared/pssm.h"

namespace penumbra {

// pssm-splits, pssm-scheme, pssm-lambda, pssm-max-splits, pssm-rho, pssm-snap, pssm-blend, pssm-split-bias.
std::vector<ParamSpec> splitParams();
// TechniqueInfo::callerMapRefusal of the split techniques (pssm, psvsm).
std::string splitsCallerMapRefusal();

// splitParams() as parsed.
struct SplitSettings {
  int count = 0;  // pssm-splits; 0 = auto
  SplitScheme scheme = SplitScheme::Practical;
  float lambda = 0;
  int maxSplits = 0;
  float rho = 0;
  bool snap = false;
  float blend = 0;
  float splitBias = 0;  // pssm-split-bias (Luksch eq. 10's delta_bias)
  // Throws std::invalid_argument for --pssm-snap on with --warp lispsm (whole-texel snapping cannot hold a warp that
  // follows the camera still).
  static SplitSettings from(const Params& params);
  bool operator==(const SplitSettings&) const = default;
};

struct SplitPlan {
  std::vector<float> distances;  // C_0 .. C_m, camera view depth
  std::vector<LightView> views;  // one per split
  std::string scheme;            // how the distances were chosen, for the header
  std::vector<LispsmFit> warps;  // --warp lispsm: how each split's warp came out; empty otherwise
  bool warpOption = false;       // the technique has --warp (pssm): the header records it
};

// The light's view cropped to the camera's frustum slice [near, far] (the split crop of planSplits), fitted with
// `marginTexels` per --fit (map-size texels).
LightView sliceLightView(const ShadowFrame& frame, const MapSettings& map, float near, float far, float marginTexels);

// Distances from the tight camera depth range of the G-buffer (a min/max reduction, as sample-distribution shadow
// maps do) and each split's light view: the minimum bounding square of its frustum slice in light space (crop),
// intersected with the visible receivers and the scene, widened by `marginTexels` (the filter's reach), optionally
// snapped; the near plane stays at the nearest caster in the scene (every caster towards the light is kept). With
// --warp lispsm (pssm) each split gets its own LiSPSM view of its slice instead (no snapping: a usage error).
SplitPlan planSplits(ShadowFrame& frame, const MapSettings& map, const SplitSettings& splits, float marginTexels);

// Draws every split's depth map (split s into `targets`, with its triangle ids when `triangleIds`, leaving out what
// can shadow no receiver when `castersOnly` (ShadowMap::castersOnly: depth comparisons, not moments), then tightens
// its zNear to the nearest caster drawn) and hands it to `each(s, depth)` before the next split reuses the targets.
template <class Each>
void drawSplits(ShadowFrame& frame, SplitPlan& plan, RasterTargets& targets, bool triangleIds, bool castersOnly,
                Each&& each);

// The kernels' per-split constants, the shared shade arguments and the light views on the device.
struct SplitGpu {
  Buffer<LightViewGpu> views;
  Buffer<PssmSplit> splits;
  std::vector<PssmSplit> host;
  PssmShade shade{};
  // `blurSigma`: the moment blur's standard deviation in texels of split 0 (psvsm; 0 for pssm).
  void upload(Context& ctx, const ShadowFrame& frame, const SplitPlan& plan, const MapSettings& map,
              const SplitSettings& splits, float blurSigma = 0.0f);
};

// Split index and resolution error AOVs of the last render ("split.Y", "resolutionError.Y").
struct SplitAovs {
  Buffer<float> split, resolutionError;
  void allocate(Context& ctx, size_t pixels);
  void addChannels(Context& ctx, Image& image) const;
};

// resolveAutoRadius (host/techniques/shadow_map.h) on split 0's map, `depth` once drawn: a split technique's radius
// is texels of split 0, which the farther splits scale by their zoom.
int resolveAutoRadiusOnSplit0(ShadowFrame& frame, const SplitPlan& plan, const Buffer<float>& depth,
                              const MapSettings& map, const AutoRadius& radius);
// resolveAutoKernel likewise: a PCF kernel's width and taps in texels of split 0, its width at most `maxWidth`.
AutoKernel resolveAutoKernelOnSplit0(ShadowFrame& frame, const SplitPlan& plan, const Buffer<float>& depth,
                                     const MapSettings& map, const AutoRadius& radius, float maxWidth);

// "penumbra:pssm-distances", "penumbra:pssm-scheme", "penumbra:light-fit" (one entry per split).
void recordSplits(ShadowFrame& frame, const SplitPlan& plan);

template <class Each>
void drawSplits(ShadowFrame& frame, SplitPlan& plan, RasterTargets& targets, bool triangleIds, bool castersOnly,
                Each&& each) {
  for (size_t s = 0; s < plan.views.size(); ++s) {
    LightView& view = plan.views[s];
    view.raster.writeTriangleIds = triangleIds;
    if (castersOnly) view.raster.casterLight = rasterLightOf(frame.light);
    frame.raster.draw(view.raster, targets);
    const size_t texels = static_cast<size_t>(view.raster.width) * static_cast<size_t>(view.raster.height);
    const DepthRange drawn = reduceDepthRange(frame.ctx, targets.depth, texels);
    if (drawn.min > view.gpu.zNear && drawn.min < view.gpu.zFar) view.gpu.zNear = drawn.min;
    each(s, targets.depth);
  }
}

}  // namespace penumbra
