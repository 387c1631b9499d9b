// `pcf`: percentage-closer filtering over a (2r+1)^2 grid of bilinear comparisons (kernels/pcf.cl).
#include "host/techniques/registry.h"
#include "host/techniques/shadow_map.h"

namespace penumbra {
namespace {

class PercentageCloser final : public Technique {
 public:
  explicit PercentageCloser(const Params& params) : params_(params) {}

  void render(ShadowFrame& frame, Buffer<float>& visibility) override {
    renderShadowMap(frame, params_.getInt("map-size"), map_);
    const GBuffer& g = frame.gbuffer;
    const BiasArgs bias = biasArgs(params_);
    const uint32_t count = static_cast<uint32_t>(g.width) * static_cast<uint32_t>(g.height);
    Kernel kernel(frame.ctx, "kernels/pcf.cl", "pcf_visibility", "shade");
    kernel.args(g.position, g.normal, count, map_.targets.depth, map_.gpu, bias.constant, bias.slope,
                bias.normalOffset, params_.getInt("pcf-radius"), visibility)
        .launch(count, kPixelGroup);
  }

 private:
  Params params_;
  ShadowMap map_;
};

}  // namespace

TechniqueInfo pcfTechnique() {
  std::vector<ParamSpec> params = shadowMapParams();
  params.push_back({"pcf-radius", 2, 0, 16, "PCF kernel radius r in texels: (2r+1)^2 bilinear taps"});
  return {"pcf", "Percentage-closer filtering with a fixed kernel", params,
          [](const Params& p) { return std::make_unique<PercentageCloser>(p); }};
}

}  // namespace penumbra
