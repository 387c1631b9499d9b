// `sm`: hard shadow map, one nearest-texel comparison or ID-buffer test (kernels/sm.cl).
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
    const GBuffer& g = frame.gbuffer;
    const ShadeFrame shade =
        shadeFrame(frame, params_, params_.getInt("receiver-plane"), params_.getInt("id-buffer"));
    launchVisibility(frame, map_, shade, "kernels/sm.cl", "sm_visibility", visibility, map_.targets.triangleId,
                     frame.raster.objectIds(), g.triangleId, g.objectId);
  }

 private:
  Params params_;
  ShadowMap map_;
};

}  // namespace

TechniqueInfo smTechnique() {
  std::vector<ParamSpec> params = shadowMapParams();
  unscaledNormalOffset(params);
  params.push_back(receiverPlaneParam());
  params.push_back(idBufferParam());
  for (ParamSpec& spec : warpParams()) params.push_back(spec);
  return {"sm", "Hard shadow map with constant, slope-scaled, normal-offset and receiver-plane depth bias", params,
          [](const Params& p) { return std::make_unique<HardShadowMap>(p); }};
}

}  // namespace penumbra
