// `pcf`: percentage-closer filtering (kernels/pcf.cl): a (2r+1)^2 grid or a rotated Poisson disk of
// bilinear comparisons, optionally widened to the pixel's footprint in the map, with receiver-plane depth
// bias. Debug channel: the kernel half-width in texels.
#include "host/techniques/poisson.h"
#include "host/techniques/registry.h"
#include "host/techniques/shadow_map.h"
#include "host/techniques/warp.h"

namespace penumbra {
namespace {

class PercentageCloser final : public Technique {
 public:
  explicit PercentageCloser(const Params& params) : params_(params) {}

  void render(ShadowFrame& frame, Buffer<float>& visibility) override {
    const bool adaptive = params_.getInt("pcf-adaptive") == 1;
    const auto limit = static_cast<float>(radiusLimit(params_, "pcf-radius"));
    const float maxRadius = std::max(static_cast<float>(params_.get("pcf-max-radius")), limit);
    renderShadowMap(frame, params_, map_, adaptive ? maxRadius : limit);
    const Params params = resolveAutoRadius(frame, map_, params_, "pcf-radius");
    const int radius = params.getInt("pcf-radius");
    const int poissonTaps = params.getInt("pcf-poisson-taps");
    if (poisson_.empty()) {
      const std::vector<cl_float2> disk = poissonDisk(std::max(poissonTaps, 1));
      poisson_ = Buffer<cl_float2>(frame.ctx, std::span<const cl_float2>(disk), CL_MEM_READ_ONLY);
    }
    filter_.allocate(frame.ctx, visibility.size());
    const GBuffer& g = frame.gbuffer;
    const ShadeFrame shade = shadeFrame(frame, params, params.getInt("receiver-plane"), params.getInt("id-buffer"));
    const PcfShade pcf{radius, static_cast<int>(adaptive), maxRadius, poissonTaps};
    launchVisibility(frame, map_, shade, "kernels/pcf.cl", "pcf_visibility", visibility, map_.targets.triangleId,
                     frame.raster.objectIds(), g.triangleId, g.objectId, pcf, poisson_, filter_);
  }

  void addDebugChannels(Context& ctx, Image& image) override { image.add("filter.Z", filter_.download(ctx)); }

 private:
  Params params_;
  ShadowMap map_;
  Buffer<cl_float2> poisson_;
  Buffer<float> filter_;
};

}  // namespace

TechniqueInfo pcfTechnique() {
  std::vector<ParamSpec> params = shadowMapParams();
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
  params.push_back({"pcf-max-radius", 16, 0, 256, "Largest adaptive half-width in texels"});
  params.push_back(
      {"pcf-poisson-taps", 0, 0, 64, "Rotated Poisson-disk taps over the kernel instead of the grid (0: grid)"});
  return {"pcf", "Percentage-closer filtering: grid or rotated Poisson taps, adaptive size, receiver-plane bias",
          params, [](const Params& p) { return std::make_unique<PercentageCloser>(p); }};
}

}  // namespace penumbra
