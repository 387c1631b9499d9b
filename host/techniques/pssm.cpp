// `pssm`: parallel-split shadow maps (Zhang et al. 2006; Lauritzen, "Parallel-Split Variance Shadow Maps"; Luksch
// sec. 7), hard or PCF per split: one map per split drawn into an atlas, then kernels/pssm.cl.
#include <algorithm>

#include "host/cl/kernel.h"
#include "host/techniques/registry.h"
#include "host/techniques/shadow_map.h"
#include "host/techniques/split_maps.h"
#include "kernels/shared/id_buffer.h"

namespace penumbra {
namespace {

enum FilterChoice { kPcf = 0, kHard = 1 };

struct PssmSettings {
  MapSettings map;
  SplitSettings splits;
  bool hard = false;  // pssm-filter hard
  AutoRadius radius;  // pcf-radius
  int idMode = ID_BUFFER_OFF;
  float maxWidth = 0.0f;  // pcf-max-radius: the auto kernel's widest, texels of split 0
  static PssmSettings from(const Params& params, int mapSize) {
    const MapSettings map = MapSettings::from(params, mapSize);
    return {map,
            SplitSettings::from(params),
            params.getInt("pssm-filter") == kHard,
            AutoRadius::from(params, "pcf-radius"),
            params.getInt("id-buffer"),
            kPcfMaxRadius.texels(params, "pcf-max-radius", map.size)};
  }
  // The most texels of split 0 the kernel can reach: the splits' margin.
  float reach() const {
    if (hard) return 0.0f;
    return radius.automatic ? std::max(maxWidth, static_cast<float>(radius.max)) : static_cast<float>(radius.radius);
  }
  bool operator==(const PssmSettings&) const = default;
};

class ParallelSplit final : public TechniqueOf<PssmSettings> {
 public:
  using TechniqueOf::TechniqueOf;

  void render(ShadowFrame& frame, Buffer<float>& visibility) override {
    Context& ctx = frame.ctx;
    const PssmSettings& set = settings_;
    const bool hard = set.hard;
    SplitPlan plan = planSplits(frame, set.map, set.splits, set.reach());
    const size_t texels = static_cast<size_t>(set.map.size) * set.map.size;
    const int idMode = set.idMode;
    AutoKernel pcf;  // hard: none; else the fixed radius or auto's, resolved on split 0
    atlas_.allocate(ctx, plan.views.size() * texels);
    idAtlas_.allocate(ctx, idMode == ID_BUFFER_OFF ? 1 : plan.views.size() * texels);
    drawSplits(frame, plan, targets_, idMode != ID_BUFFER_OFF, true, [&](size_t s, const Buffer<float>& depth) {
      if (s == 0 && !hard) pcf = resolveAutoKernelOnSplit0(frame, plan, depth, set.map, set.radius, set.maxWidth);
      copyInto(ctx, depth, atlas_, s * texels, texels);
      if (idMode != ID_BUFFER_OFF) copyInto(ctx, targets_.triangleId, idAtlas_, s * texels, texels);
    });
    gpu_.upload(ctx, frame, plan, set.map, set.splits);
    gpu_.shade.radius = pcf.radius;
    gpu_.shade.pcfWidth = pcf.width;
    gpu_.shade.idMode = idMode;
    recordSplits(frame, plan);

    const GBuffer& g = frame.gbuffer;
    const size_t pixels = static_cast<size_t>(g.width) * g.height;
    aovs_.allocate(ctx, pixels);
    Kernel kernel(ctx, "kernels/pssm.cl", "pssm_visibility", "shade");
    kernel
        .args(g.position, g.normal, g.depth, atlas_, idAtlas_, frame.raster.objectIds(), g.triangleId, g.objectId,
              gpu_.views, gpu_.splits, gpu_.shade, visibility, aovs_.split,
              aovs_.resolutionError)
        .moves(pixels * (kVisibilityBytesPerPixel + 4 + 8))  // + camera depth read, split and error AOVs written
        .launch(pixels, pixelGroup(frame.ctx));
  }

  void addDebugChannels(Context& ctx, Image& image) override { aovs_.addChannels(ctx, image); }

 private:
  RasterTargets targets_;
  Buffer<float> atlas_;
  Buffer<uint32_t> idAtlas_;  // the splits' triangle ids with an ID buffer, else one unused element
  SplitGpu gpu_;
  SplitAovs aovs_;
};

}  // namespace

TechniqueInfo pssmTechnique() {
  std::vector<ParamSpec> params = shadowMapParams();
  shortPenumbraMapSize(params);  // a hard lookup or a PCF kernel of at most --pcf-radius-max texels, as sm and pcf
  splitMapSize(params);
  params.push_back(
      {"pssm-filter", kPcf, 0, 1, "Per-split lookup: PCF over --pcf-radius, or one hard comparison", {"pcf", "hard"}});
  for (const ParamSpec& spec : pcfRadiusParams()) params.push_back(spec);
  params.push_back(kPcfMaxRadius.param("pcf-max-radius", 0, 256,
                                       "--pcf-radius auto: the kernel's largest half-width in texels of split 0 "
                                       "(beyond --pcf-radius-max the taps spread over the kernel)"));
  params.push_back(idBufferParam());
  for (const ParamSpec& spec : splitParams()) params.push_back(spec);
  for (const ParamSpec& spec : warpParams()) params.push_back(spec);
  TechniqueInfo info{"pssm", "Parallel-split shadow maps, hard or PCF per split (uniform/log/practical/auto splits)",
                     params, makeTechnique<ParallelSplit>};
  info.callerMapRefusal = splitsCallerMapRefusal();
  return info;
}

}  // namespace penumbra
