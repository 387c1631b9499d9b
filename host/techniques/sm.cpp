// `sm`: hard shadow map, one nearest-texel comparison (kernels/sm.cl).
#include "host/techniques/registry.h"
#include "host/techniques/shadow_map.h"
#include "host/techniques/warp.h"

namespace penumbra {
namespace {

class HardShadowMap final : public Technique {
 public:
  explicit HardShadowMap(const Params& params) : params_(params) {}

  void render(ShadowFrame& frame, Buffer<float>& visibility) override {
    renderShadowMap(frame, params_, map_, 0.0f);
    launchVisibility(frame, map_, params_, "kernels/sm.cl", "sm_visibility", visibility,
                     params_.getInt("receiver-plane"));
  }

 private:
  Params params_;
  ShadowMap map_;
};

}  // namespace

TechniqueInfo smTechnique() {
  std::vector<ParamSpec> params = shadowMapParams();
  params.push_back(receiverPlaneParam());
  for (ParamSpec& spec : warpParams()) params.push_back(spec);
  return {"sm", "Hard shadow map with constant, slope-scaled, normal-offset and receiver-plane depth bias", params,
          [](const Params& p) { return std::make_unique<HardShadowMap>(p); }};
}

}  // namespace penumbra
