// `psvsm`: parallel-split variance shadow maps (Lauritzen, "Parallel-Split Variance Shadow Maps", steps 1-7): per
// split a shadow map, VSM moments over its own depth range, a blur scaled by the split's zoom (step 2d) and a mip
// chain (2e), gathered in atlases; then kernels/psvsm.cl.
#include <cmath>

#include "host/cl/kernel.h"
#include "host/stages/pyramid.h"
#include "host/techniques/moment_map.h"
#include "host/techniques/registry.h"
#include "host/techniques/split_maps.h"

namespace penumbra {
namespace {

class ParallelSplitVariance final : public Technique {
 public:
  explicit ParallelSplitVariance(const Params& params) : params_(params) {}

  void render(ShadowFrame& frame, Buffer<float>& visibility) override {
    Context& ctx = frame.ctx;
    const uint32_t size = static_cast<uint32_t>(params_.getInt("map-size"));
    const ImageShape shape{size, size, 2};
    const BlurConfig blurBase = blurConfig();
    SplitPlan plan = planSplits(frame, params_, blurReach(blurBase));
    const bool trilinear = params_.getInt("moment-filtering") == 1;
    const PyramidLayout layout = pyramidLayout(size, size, 1);
    const size_t mipTexels = trilinear ? layout.texels : 0;
    base_.allocate(ctx, plan.views.size() * shape.count());
    mipAtlas_.allocate(ctx, plan.views.size() * mipTexels * 2);
    moments_.allocate(ctx, shape.count());
    if (trilinear) mips_.allocate(ctx, mipTexels * 2);
    drawSplits(frame, plan, targets_, [&](size_t s, const Buffer<float>& depth) {
      const LightViewGpu& v = plan.views[s].gpu;
      MomentsConfig config;
      config.depthNear = v.zNear, config.depthFar = v.zFar;
      if (params_.getInt("blur-radius") > 0) {
        BlurConfig scaled = blurBase;  // step 2d: the kernel shrinks with the split's zoom (texels of split 0)
        scaled.scale = plan.views[0].gpu.texelScale / v.texelScale;
        scratch_.allocate(ctx, shape.count());
        blurMoments(ctx, depth, config, moments_, scratch_, size, size, scaled);
      } else {
        computeMoments(ctx, depth, size, size, config, moments_);
      }
      copyInto(ctx, moments_, base_, s * shape.count(), shape.count());
      if (!trilinear) return;
      computeMomentMips(ctx, moments_, shape, mips_);  // step 2e
      copyInto(ctx, mips_, mipAtlas_, s * mipTexels * 2, mipTexels * 2);
    });
    mipLevels_.allocate(ctx, trilinear ? layout.levels.size() : 0, CL_MEM_READ_ONLY);
    if (trilinear) mipLevels_.upload(ctx, std::span<const PyramidLevel>(layout.levels));
    const float sigma = params_.getInt("blur-radius") > 0 ? blurBase.sigma : 0.0f;
    gpu_.upload(ctx, frame, plan, params_, sigma);
    gpu_.shade.mipTexels = static_cast<uint32_t>(mipTexels);
    recordSplits(frame, plan);

    ShadowMap first;  // momentShade's common fields; the kernel replaces the normalisation per split
    first.view = plan.views[0];
    MomentShade shade = momentShade(frame, first, params_, 2);
    setChebyshevShade(params_, shade);
    shade.levels = trilinear ? static_cast<uint32_t>(layout.levels.size()) + 1 : 1;
    const GBuffer& g = frame.gbuffer;
    const size_t pixels = static_cast<size_t>(g.width) * g.height;
    aovs_.allocate(ctx, pixels);
    Kernel kernel(ctx, "kernels/psvsm.cl", "psvsm_visibility", "shade");
    kernel
        .args(g.position, g.normal, g.depth, gpu_.views, gpu_.splits, base_, mipAtlas_, mipLevels_, shade,
              gpu_.shade, visibility, aovs_.split, aovs_.resolutionError)
        .moves(pixels * (kVisibilityBytesPerPixel + 4 + 8))  // + camera depth read, split and error AOVs written
        .launch(pixels, kPixelGroup);
  }

  void addDebugChannels(Context& ctx, Image& image) override { aovs_.addChannels(ctx, image); }

 private:
  // As the vsm family's: a box of 2r+1 taps or a Gaussian of the same variance r(r+1)/3.
  BlurConfig blurConfig() const {
    BlurConfig config;
    const int radius = params_.getInt("blur-radius");
    config.filter = params_.getInt("blur-filter") == 1 ? BlurFilter::Box : BlurFilter::Gaussian;
    config.radius = radius;
    config.sigma = static_cast<float>(std::sqrt(radius * (radius + 1.0) / 3.0));
    return config;
  }
  float blurReach(const BlurConfig& c) const {
    if (params_.getInt("blur-radius") == 0) return 0.0f;
    return c.filter == BlurFilter::Box ? static_cast<float>(c.radius) : std::ceil(3.0f * c.sigma);
  }

  Params params_;
  RasterTargets targets_;
  Buffer<float> moments_, scratch_, mips_, base_, mipAtlas_;
  Buffer<PyramidLevel> mipLevels_;
  SplitGpu gpu_;
  SplitAovs aovs_;
};

}  // namespace

TechniqueInfo psvsmTechnique() {
  std::vector<ParamSpec> params = filteredMomentParams(chebyshevParams());
  for (ParamSpec& spec : params)
    if (spec.name == "moment-filtering") spec.defaultValue = 1;  // step 2e: mipmapped (trilinear) lookups
  for (const ParamSpec& spec : splitParams()) params.push_back(spec);
  return {"psvsm", "Parallel-split variance shadow maps: VSM per split, blur scaled by zoom, mipmaps", params,
          [](const Params& p) { return std::make_unique<ParallelSplitVariance>(p); }};
}

}  // namespace penumbra
