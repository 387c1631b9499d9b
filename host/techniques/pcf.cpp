// `pcf`: percentage-closer filtering (kernels/pcf.cl): a (2r+1)^2 grid or a rotated Poisson disk of
// bilinear comparisons, optionally widened to the pixel's footprint in the map, with receiver-plane depth
// bias. Debug channel: the kernel half-width in texels.
#include <algorithm>

#include "host/techniques/poisson.h"
#include "host/techniques/registry.h"
#include "host/techniques/shadow_map.h"
#include "host/techniques/warp.h"
#include "kernels/shared/id_buffer.h"

namespace penumbra {
namespace {

struct PcfSettings {
  MapSettings map;
  int receiverPlane = 1;
  int idMode = ID_BUFFER_OFF;
  AutoRadius radius;
  bool adaptive = false;
  float maxRadius = 0;  // pcf-max-radius
  int poissonTaps = 0;
  static PcfSettings from(const Params& params, int mapSize) {
    const MapSettings map = MapSettings::from(params, mapSize);
    return {map,
            params.getInt("receiver-plane"),
            params.getInt("id-buffer"),
            AutoRadius::from(params, "pcf-radius"),
            params.getInt("pcf-adaptive") == 1,
            kPcfMaxRadius.texels(params, "pcf-max-radius", map.size),
            params.getInt("pcf-poisson-taps")};
  }
  bool operator==(const PcfSettings&) const = default;
};

class PercentageCloser final : public TechniqueOf<PcfSettings> {
 public:
  using TechniqueOf::TechniqueOf;

  void render(ShadowFrame& frame, Buffer<float>& visibility) override {
    const PcfSettings& s = settings_;
    const auto limit = static_cast<float>(s.radius.limit());
    const float maxRadius = std::max(s.maxRadius, limit);
    // Depth comparisons only: the auto radius's occluders lie at or beyond the nearest drawn caster anyway. Under auto
    // the kernel may reach --pcf-max-radius texels, so the map's margin does.
    map_.triangleIds = s.idMode != ID_BUFFER_OFF;
    map_.castersOnly = true;  // the map leaves out what can shadow no receiver
    renderShadowMap(frame, s.map, map_, s.adaptive || s.radius.automatic ? maxRadius : limit, MapNear::Fitted);
    const AutoKernel kernel =
        resolveAutoKernel(frame, map_.targets.depth, map_.gpu, s.map.receiverBias(), s.radius, maxRadius);
    const int poissonTaps = s.poissonTaps;
    if (poisson_.empty()) {
      const std::vector<cl_float2> disk = poissonDisk(std::max(poissonTaps, 1));
      poisson_ = Buffer<cl_float2>(frame.ctx, std::span<const cl_float2>(disk), CL_MEM_READ_ONLY);
    }
    filter_.allocate(frame.ctx, visibility.size());
    const GBuffer& g = frame.gbuffer;
    const ShadeFrame shade = shadeFrame(frame, s.map, s.receiverPlane, s.idMode);
    const PcfShade pcf{kernel.radius, static_cast<int>(s.adaptive), maxRadius, poissonTaps, kernel.width};
    launchVisibility(frame, map_, shade, "kernels/pcf.cl", "pcf_visibility", visibility, map_.targets.triangleId,
                     frame.raster.objectIds(), g.triangleId, g.objectId, pcf, poisson_, filter_);
  }

  void addDebugChannels(Context& ctx, Image& image) override { image.add("filter.Z", filter_.download(ctx)); }

 private:
  ShadowMap map_;
  Buffer<cl_float2> poisson_;
  Buffer<float> filter_;
};

}  // namespace

TechniqueInfo pcfTechnique() {
  std::vector<ParamSpec> params = shadowMapParams();
  shortPenumbraMapSize(params);
  params.push_back(receiverPlaneParam());
  params.push_back(idBufferParam());
  for (ParamSpec& spec : warpParams()) params.push_back(spec);
  // The radius from the scene's penumbrae, without the adaptive widening: docs/techniques/sm-pcf-pcss.md.
  for (const ParamSpec& spec : pcfRadiusParams()) params.push_back(spec);
  params.push_back({"pcf-adaptive",
                    0,
                    0,
                    1,
                    "Widen the kernel to half the pixel's footprint in the map (minified shadows), same tap count",
                    {"off", "on"}});
  params.push_back(kPcfMaxRadius.param("pcf-max-radius", 0, 256,
                                       "Largest kernel half-width in texels: the adaptive widening's, and --pcf-radius "
                                       "auto's (beyond --pcf-radius-max the taps spread over the kernel)"));
  params.push_back(
      {"pcf-poisson-taps", 0, 0, 64, "Rotated Poisson-disk taps over the kernel instead of the grid (0: grid)"});
  return {"pcf", "Percentage-closer filtering: grid or rotated Poisson taps, adaptive size, receiver-plane bias",
          params, makeTechnique<PercentageCloser>};
}

}  // namespace penumbra
