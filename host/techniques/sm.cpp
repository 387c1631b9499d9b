// `sm`: hard shadow map, one nearest-texel comparison or ID-buffer test (kernels/sm.cl).
#include "host/techniques/registry.h"
#include "host/techniques/shadow_map.h"
#include "host/techniques/warp.h"
#include "kernels/shared/id_buffer.h"

namespace penumbra {
namespace {

struct SmSettings {
  MapSettings map;
  int receiverPlane = 1;
  int idMode = ID_BUFFER_OFF;
  static SmSettings from(const Params& params, int mapSize) {
    return {MapSettings::from(params, mapSize), params.getInt("receiver-plane"), params.getInt("id-buffer")};
  }
  bool operator==(const SmSettings&) const = default;
};

class HardShadowMap final : public TechniqueOf<SmSettings> {
 public:
  using TechniqueOf::TechniqueOf;

  void render(ShadowFrame& frame, Buffer<float>& visibility) override {
    map_.triangleIds = settings_.idMode != ID_BUFFER_OFF;
    map_.castersOnly = true;  // the map leaves out what can shadow no receiver
    renderShadowMap(frame, settings_.map, map_, 0.0f, MapNear::Fitted);  // depth comparisons only
    const GBuffer& g = frame.gbuffer;
    const ShadeFrame shade = shadeFrame(frame, settings_.map, settings_.receiverPlane, settings_.idMode);
    launchVisibility(frame, map_, shade, "kernels/sm.cl", "sm_visibility", visibility, map_.targets.triangleId,
                     frame.raster.objectIds(), g.triangleId, g.objectId);
  }

 private:
  ShadowMap map_;
};

}  // namespace

TechniqueInfo smTechnique() {
  std::vector<ParamSpec> params = shadowMapParams();
  unscaledNormalOffset(params);
  shortPenumbraMapSize(params);
  params.push_back(receiverPlaneParam());
  params.push_back(idBufferParam());
  for (ParamSpec& spec : warpParams()) params.push_back(spec);
  return {"sm", "Hard shadow map with constant, slope-scaled, normal-offset and receiver-plane depth bias", params,
          makeTechnique<HardShadowMap>};
}

}  // namespace penumbra
