// `pcf`: percentage-closer filtering over a (2r+1)^2 grid of bilinear comparisons (kernels/pcf.cl).
#include "host/techniques/registry.h"
#include "host/techniques/shadow_map.h"

namespace penumbra {
namespace {

class PercentageCloser final : public Technique {
 public:
  explicit PercentageCloser(const Params& params) : params_(params) {}

  void render(ShadowFrame& frame, Buffer<float>& visibility) override {
    renderShadowMap(frame, params_, map_, static_cast<float>(params_.getInt("pcf-radius")));
    launchVisibility(frame, map_, params_, "kernels/pcf.cl", "pcf_visibility", visibility,
                     params_.getInt("pcf-radius"));
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
