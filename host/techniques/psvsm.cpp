// `psvsm`: parallel-split variance shadow maps (Lauritzen, "Parallel-Split Variance Shadow Maps", steps 1-7): per
// split a shadow map, VSM moments over its own depth range, a blur scaled by the split's zoom (step 2d) and a mip
// chain (2e), gathered in atlases, stored fp32 or half (moment-storage); then kernels/psvsm.cl.
#include "host/cl/kernel.h"
#include "host/stages/pyramid.h"
#include "host/techniques/moment_map.h"
#include "host/techniques/registry.h"
#include "host/techniques/split_maps.h"

namespace penumbra {
namespace {

struct PsvsmSettings {
  MapSettings map;
  SplitSettings splits;
  MomentFilter filter;
  MomentStorage storage = MomentStorage::Float32;
  Chebyshev chebyshev;
  static PsvsmSettings from(const Params& params, int mapSize) {
    const MapSettings map = MapSettings::from(params, mapSize);
    return {map, SplitSettings::from(params), MomentFilter::from(params, map.size), momentStorage(params),
            Chebyshev::from(params)};
  }
  bool operator==(const PsvsmSettings&) const = default;
};

class ParallelSplitVariance final : public TechniqueOf<PsvsmSettings> {
 public:
  using TechniqueOf::TechniqueOf;

  void render(ShadowFrame& frame, Buffer<float>& visibility) override {
    Context& ctx = frame.ctx;
    const PsvsmSettings& set = settings_;
    const uint32_t size = static_cast<uint32_t>(set.map.size);
    const ImageShape shape{size, size, 2};
    SplitPlan plan = planSplits(frame, set.map, set.splits, momentBlurReach(set.filter));
    const bool trilinear = set.filter.trilinear;
    const PyramidLayout layout = pyramidLayout(size, size, 1);
    const size_t mipTexels = trilinear ? layout.texels : 0;
    const MomentStorage storage = set.storage;
    blurRadius_ = set.filter.blur.radius;  // resolved on split 0 under auto
    if (storage == MomentStorage::Float16) {
      maps_.clear(ctx);
      drawMoments(frame, plan, shape, mipTexels, storage, maps16_);
    } else {
      maps16_.clear(ctx);
      drawMoments(frame, plan, shape, mipTexels, storage, maps_);
    }
    mipLevels_.allocate(ctx, trilinear ? layout.levels.size() : 0, CL_MEM_READ_ONLY);
    if (trilinear) mipLevels_.upload(ctx, std::span<const PyramidLevel>(layout.levels));
    // Split 0's (blur-radius resolved on its map), scaled per split.
    const float sigma = momentBlurConfig(set.filter, blurRadius_).sigma;
    gpu_.upload(ctx, frame, plan, set.map, set.splits, sigma);
    gpu_.shade.mipTexels = static_cast<uint32_t>(mipTexels);
    recordSplits(frame, plan);

    ShadowMap first;  // momentShade's common fields; the kernel replaces the normalisation per split
    first.view = plan.views[0];
    MomentShade shade = momentShade(frame, first, set.map, set.filter.filterBias, 2);
    set.chebyshev.apply(shade);
    shade.levels = trilinear ? static_cast<uint32_t>(layout.levels.size()) + 1 : 1;
    const GBuffer& g = frame.gbuffer;
    const size_t pixels = static_cast<size_t>(g.width) * g.height;
    aovs_.allocate(ctx, pixels);
    Kernel kernel(ctx, "kernels/psvsm.cl", "psvsm_visibility", "shade", storageOptions(storage));
    const auto lookups = [&](const auto& maps) {  // the storage in use (float or cl_half)
      kernel.args(g.position, g.normal, g.depth, gpu_.views, gpu_.splits, maps.base, maps.mipAtlas, mipLevels_, shade,
                  gpu_.shade, visibility, aovs_.split, aovs_.resolutionError);
    };
    if (storage == MomentStorage::Float16)
      lookups(maps16_);
    else
      lookups(maps_);
    kernel
        .moves(pixels * (kVisibilityBytesPerPixel + 4 + 8))  // + camera depth read, split and error AOVs written
        .launch(pixels, pixelGroup(frame.ctx));
  }

  void addDebugChannels(Context& ctx, Image& image) override { aovs_.addChannels(ctx, image); }

 private:
  // Every split's moments and mips in storage T (float or cl_half), gathered in atlases.
  template <class T>
  struct Maps {
    Buffer<T> moments, mips;    // one split's, before the copy into the atlases
    Buffer<T> base, mipAtlas;   // split-major atlases the kernel reads
    void clear(Context& ctx) {  // the storage not in use keeps no memory
      for (Buffer<T>* b : {&moments, &mips, &base, &mipAtlas}) b->allocate(ctx, 0);
    }
  };

  // Steps 2c-2e per split: moments over its own depth range, the blur scaled by its zoom, the mip chain; blur-radius
  // auto measured on split 0's map, once it is drawn (its radius is texels of split 0).
  template <class T>
  void drawMoments(ShadowFrame& frame, SplitPlan& plan, const ImageShape& shape, size_t mipTexels,
                   MomentStorage storage, Maps<T>& maps) {
    Context& ctx = frame.ctx;
    maps.base.allocate(ctx, plan.views.size() * shape.count());
    maps.mipAtlas.allocate(ctx, plan.views.size() * mipTexels * 2);
    maps.moments.allocate(ctx, shape.count());
    if (mipTexels > 0) maps.mips.allocate(ctx, mipTexels * 2);
    drawSplits(frame, plan, targets_, false, false, [&](size_t s, const Buffer<float>& depth) {
      const LightViewGpu& v = plan.views[s].gpu;
      if (s == 0) blurRadius_ = resolveAutoRadiusOnSplit0(frame, plan, depth, settings_.map, settings_.filter.blur);
      MomentsConfig config;
      config.depthNear = v.zNear, config.depthFar = v.zFar;
      config.storage = storage;
      if (blurRadius_ > 0) {
        // Step 2d: the kernel shrinks with the split's zoom (texels of split 0).
        BlurConfig scaled = momentBlurConfig(settings_.filter, blurRadius_);
        scaled.scale = plan.views[0].gpu.texelScale / v.texelScale;
        scratch_.allocate(ctx, blurMomentsScratch(ctx, shape, scaled, storage, config.kind));
        blurMoments(ctx, depth, config, maps.moments, scratch_, shape.width, shape.height, scaled);
      } else {
        computeMoments(ctx, depth, shape.width, shape.height, config, maps.moments);
      }
      copyInto(ctx, maps.moments, maps.base, s * shape.count(), shape.count());
      if (mipTexels == 0) return;
      computeMomentMips(ctx, maps.moments, shape, maps.mips);  // step 2e
      copyInto(ctx, maps.mips, maps.mipAtlas, s * mipTexels * 2, mipTexels * 2);
    });
  }

  int blurRadius_ = 0;  // this frame's blur-radius: resolved on split 0 under auto
  RasterTargets targets_;
  Buffer<float> scratch_;
  Maps<float> maps_;
  Maps<cl_half> maps16_;
  Buffer<PyramidLevel> mipLevels_;
  SplitGpu gpu_;
  SplitAovs aovs_;
};

}  // namespace

TechniqueInfo psvsmTechnique() {
  std::vector<ParamSpec> params = momentMapParams(chebyshevParams());
  blurredPenumbraMapSize(params);  // moments blurred with one radius per frame, as vsm
  splitMapSize(params);
  // Bilinear lookups by default; step 2e's mipmapped (trilinear) lookups are --moment-filtering trilinear. The mip
  // level follows the pixel's longer footprint axis, which against visibility at the pixel's centre washes out thin
  // casters and holes (builtin:poles MAE 0.0120 vs 0.0059, builtin:cards 0.0197 vs 0.0022 at 480x270) while gaining
  // 20-55 % on box, stacked-planes and staircase: docs/techniques/pssm.md ("Bilinear lookups by default").
  for (const ParamSpec& spec : splitParams()) params.push_back(spec);
  TechniqueInfo info{"psvsm",
                     "Parallel-split variance shadow maps: VSM per split, blur scaled by zoom, optional mipmaps",
                     params, makeTechnique<ParallelSplitVariance>};
  info.callerMapRefusal = splitsCallerMapRefusal();
  return info;
}

}  // namespace penumbra
