// `pcss`: percentage-closer soft shadows for spot disk lights and sun disks (kernels/pcss.cl): blocker
// search, penumbra from similar triangles, PCF. Debug channel: the average blocker depth.
#include "host/techniques/registry.h"
#include "host/techniques/shadow_map.h"

namespace penumbra {
namespace {

class PercentageCloserSoft final : public Technique {
 public:
  explicit PercentageCloserSoft(const Params& params) : params_(params) {}

  void render(ShadowFrame& frame, Buffer<float>& visibility) override {
    renderShadowMap(frame, params_, map_, static_cast<float>(params_.get("pcss-max-radius")));
    blocker_.allocate(frame.ctx, visibility.size());
    launchVisibility(frame, map_, params_, "kernels/pcss.cl", "pcss_visibility", visibility,
                     params_.getInt("receiver-plane"),
                     params_.getInt("pcss-search-taps"), params_.getInt("pcss-filter-taps"),
                     static_cast<float>(params_.get("pcss-max-radius")), blocker_);
  }

  void addDebugChannels(Context& ctx, Image& image) override { image.add("blocker.Z", blocker_.download(ctx)); }

 private:
  Params params_;
  ShadowMap map_;
  Buffer<float> blocker_;
};

}  // namespace

TechniqueInfo pcssTechnique() {
  std::vector<ParamSpec> params = shadowMapParams();
  params.push_back(receiverPlaneParam());
  params.push_back({"pcss-search-taps", 8, 1, 64, "Blocker-search grid: taps x taps samples"});
  params.push_back({"pcss-filter-taps", 8, 1, 64, "PCF grid: taps x taps bilinear comparisons"});
  params.push_back({"pcss-max-radius", 64, 1, 512, "Largest search/filter half-width in texels"});
  return {"pcss", "Percentage-closer soft shadows (blocker search + PCF) for area lights", params,
          [](const Params& p) { return std::make_unique<PercentageCloserSoft>(p); }};
}

}  // namespace penumbra
