// `savsm`: summed-area variance shadow maps (Lauritzen, GPU Gems 3 ch. 8, sec. 8.5): VSM moments ->
// summed-area table in the selected precision (host/stages/sat.h) -> one box lookup per pixel whose width
// is fixed, follows the light's penumbra at a typical occluder distance, or the pixel footprint
// (kernels/savsm.cl).
#include <fmt/format.h>

#include <algorithm>
#include <stdexcept>
#include <string>

#include "host/cl/kernel.h"
#include "host/stages/sat.h"
#include "host/techniques/moment_map.h"
#include "host/techniques/registry.h"

namespace penumbra {
namespace {

enum Precision { kFloat = 0, kFixed32 = 1, kFixed64 = 2, kDouble = 3 };
constexpr double kAutoDistance = -1.0;  // savsm-occluder-distance auto (outside [0, 1e6])

struct SavsmSettings {
  MapSettings map;
  Chebyshev chebyshev;
  float filterBias = 0;
  uint32_t widthFrom = MOMENT_WIDTH_LIGHT;  // MOMENT_WIDTH_*
  float width = 0, maxWidth = 0;            // savsm-width, savsm-max-width
  bool autoDistance = false;                // savsm-occluder-distance auto
  float occluderDistance = 0;
  double distanceQuantile = 0;
  Precision precision = kFixed32;  // sat-precision
  // Throws std::invalid_argument when savsm-width is above savsm-max-width.
  static SavsmSettings from(const Params& params, int mapSize) {
    if (params.get("savsm-width") > params.get("savsm-max-width"))
      throw std::invalid_argument(fmt::format("--savsm-width {} is larger than --savsm-max-width {}",
                                              params.get("savsm-width"), params.get("savsm-max-width")));
    SavsmSettings s;
    s.map = MapSettings::from(params, mapSize);
    s.chebyshev = Chebyshev::from(params);
    s.filterBias = static_cast<float>(params.get("filter-bias"));
    s.widthFrom = static_cast<uint32_t>(params.getInt("savsm-width-from"));
    s.width = static_cast<float>(params.get("savsm-width"));
    s.maxWidth = static_cast<float>(params.get("savsm-max-width"));
    s.autoDistance = params.isAuto("savsm-occluder-distance");
    s.occluderDistance = s.autoDistance ? 0.0f : static_cast<float>(params.get("savsm-occluder-distance"));
    s.distanceQuantile = params.get("savsm-occluder-distance-quantile");
    s.precision = static_cast<Precision>(params.getInt("sat-precision"));
    return s;
  }
  bool operator==(const SavsmSettings&) const = default;
};

class SummedAreaVsm final : public TechniqueOf<SavsmSettings> {
 public:
  using TechniqueOf::TechniqueOf;

  void render(ShadowFrame& frame, Buffer<float>& visibility) override {
    const int size = settings_.map.size;
    renderShadowMap(frame, settings_.map, map_, 0.5f * settings_.maxWidth);
    MomentsConfig config;
    config.depthNear = map_.view.gpu.zNear;
    config.depthFar = map_.view.gpu.zFar;
    shape_ = {static_cast<uint32_t>(size), static_cast<uint32_t>(size), 2};
    moments_.allocate(frame.ctx, shape_.count());
    computeMoments(frame.ctx, map_.targets.depth, shape_.width, shape_.height, config, moments_);
    switch (settings_.precision) {
      case kFixed32:
        return shade<uint32_t>(frame, visibility);
      case kFixed64:
        return shade<uint64_t>(frame, visibility);
      case kDouble:
        return shade<double>(frame, visibility);
      default:
        return shade<float>(frame, visibility);
    }
  }

  void addDebugChannels(Context& ctx, Image& image) override { debug_.addChannels(ctx, image, 2, true, true); }

 private:
  // SAT of the moments in storage T, then the visibility kernel built for that storage.
  template <class T>
  void shade(ShadowFrame& frame, Buffer<float>& visibility) {
    Context& ctx = frame.ctx;
    MomentShade s = momentShade(frame, map_, settings_.map, settings_.filterBias, 2);
    settings_.chebyshev.apply(s);
    s.widthMode = settings_.widthFrom;
    s.filterWidth = settings_.width;
    s.maxWidth = settings_.maxWidth;
    s.occluderDistance = occluderDistance(frame);

    SatConfig satConfig;
    constexpr uint32_t mode = satMode<T>();
    if (mode == SAT_MODE_FIXED32 || mode == SAT_MODE_FIXED64) {
      const double side = s.maxWidth + 2.0;  // a box plus the texels its fractional corners touch
      satConfig.fractionBits = satFractionBits(mode, side * side, 1.0);  // moments lie in [0, 1]
    }
    Buffer<T> table(ctx, shape_.count());
    Buffer<float> offset(ctx, 4);
    computeSat(ctx, moments_, shape_, table, offset, satConfig);
    const SatTableDesc desc = satDesc(shape_, mode, satConfig.fractionBits);

    const GBuffer& g = frame.gbuffer;
    const size_t pixels = size_t(s.width) * s.height;
    debug_.allocate(ctx, pixels);
    Kernel kernel(ctx, "kernels/savsm.cl", "savsm_visibility", "shade", satBuildOptions(desc));
    kernel.args(g.position, g.normal, map_.gpu, table, desc, offset, s, visibility, debug_.moments, debug_.stats)
        .moves(pixels * kVisibilityBytesPerPixel)
        .launch(pixels, pixelGroup(frame.ctx));
  }

  // savsm-occluder-distance, or under auto its quantile over the camera's pixels in the map's hard shadow (in units
  // of the scene's size / 16, so the histogram's range suits any scale), recorded in the header.
  float occluderDistance(ShadowFrame& frame) const {
    if (!settings_.autoDistance) return settings_.occluderDistance;
    const double quantile = settings_.distanceQuantile;
    const float unit = std::max(frame.scene.bounds().orUnit().radius(), 1e-6f) / 16.0f;
    const OccluderDistance d = measureOccluderDistance(frame.ctx, frame.gbuffer, map_.targets.depth, map_.gpu,
                                                       settings_.map.receiverBias(), quantile, unit);
    frame.attributes["penumbra:savsm-occluder-distance"] =
        d.pixels == 0 ? std::string("auto 0 (no shadowed pixel measured)")
                      : fmt::format("auto {:.4g} (quantile {} of {} shadowed pixels)", d.distance, quantile, d.pixels);
    return static_cast<float>(d.distance);
  }

  ShadowMap map_;
  ImageShape shape_;
  Buffer<float> moments_;
  MomentDebug debug_;
};

}  // namespace

TechniqueInfo savsmTechnique() {
  std::vector<ParamSpec> params = shadowMapParams();
  blurredPenumbraMapSize(params);
  const std::vector<ParamSpec> chebyshev = chebyshevParams();
  params.insert(params.end(), chebyshev.begin(), chebyshev.end());
  params.push_back(filterBiasParam());
  params.push_back(
      {"savsm-width-from",
       MOMENT_WIDTH_LIGHT,
       0,
       2,
       "SAVSM filter width: fixed, the light's penumbra at savsm-occluder-distance, or the pixel footprint",
       {"fixed", "light", "footprint"}});
  // Auto distance and a smallest width of 1 (3 before): measured in docs/techniques/moments.md (savsm).
  params.push_back(
      {"savsm-width", 1, 1, 4096, "SAVSM filter width in texels (fixed), and the smallest width otherwise"});
  params.push_back({"savsm-max-width", 64, 1, 4096, "Largest SAVSM filter width in texels"});
  ParamSpec distance{"savsm-occluder-distance", kAutoDistance, 0, 1e6,
                     "Typical occluder-to-receiver distance along the light axis (world units) for the light width; "
                     "auto: the distance --savsm-occluder-distance-quantile of the shadowed pixels' occluders reach"};
  distance.autoName = "auto";
  distance.autoValue = kAutoDistance;
  params.push_back(distance);
  params.push_back({"savsm-occluder-distance-quantile", 0.1, 0.01, 1,
                    "--savsm-occluder-distance auto: the share of the camera's shadowed pixels whose occluder is at "
                    "most that far in front of them"});
  params.push_back({"sat-precision",
                    kFixed32,
                    0,
                    3,
                    "Summed-area table storage (double needs a device with fp64)",
                    {"float", "fixed32", "fixed64", "double"}});
  return {"savsm", "Summed-area variance shadow maps with a per-pixel filter width", params,
          makeTechnique<SummedAreaVsm>};
}

}  // namespace penumbra
