// Moment shadow map pipeline shared by vsm, evsm2/4, esm and msm: plans the buffers, then records
// renderShadowMap, moments, blur, mips and the visibility kernel as named passes.
#include "host/techniques/moment_map.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "host/cl/kernel.h"
#include "host/stages/blur.h"
#include "host/stages/pyramid.h"

namespace penumbra {
namespace {

enum BlurChoice { kGaussian = 0, kBox = 1 };
enum SamplingChoice { kBilinear = 0, kTrilinear = 1 };
enum StorageChoice { kFp32 = 0, kFp16 = 1 };

// --blur-radius-max auto: a 128th of the map's side, at least 16, so that the blur reaches as far in the scene at every
// map size and a larger map never draws a penumbra harder than a smaller one: builtin:staircase at 480x270 with a
// fixed 16, vsm's MAE 0.00325 / 0.00332 / 0.00496 at 1024 / 2048 / 4096^2 (msm 0.00310 / 0.00321 / 0.00490; its
// narrow end reaches 36 texels at 4096^2); with 32 at 4096^2: 0.00329 (msm 0.00321). Up to 2048^2 it is the fixed 16
// it replaces.
constexpr int kAutoBlurMax = -1;  // outside [0, 64]
constexpr int kBlurMaxDivisor = 128, kMinAutoBlurMax = 16;

}  // namespace

std::vector<ParamSpec> momentFilterParams() {
  std::vector<ParamSpec> params = autoRadiusParams(
      "blur-radius",
      "Moment blur half-width r in texels: a box of 2r+1 taps or a Gaussian of the same variance; 0 = off", 64,
      kAutoBlurMax,
      "; auto: a 128th of the map's side, at least 16 (esm, evsm2: 2, their positive warp alone lets the deeper "
      "receivers a wider kernel covers light the pixel)");
  ParamSpec& max = paramNamed(params, "blur-radius-max");
  max.autoName = "auto";
  max.autoValue = kAutoBlurMax;
  const std::vector<ParamSpec> rest = {
      {"blur-filter", kGaussian, 0, 1, "Moment blur filter", {"gaussian", "box"}},
      {"moment-filtering",
       kBilinear,
       0,
       1,
       "Moment lookups: bilinear, or trilinear over a mip chain with the pixel's footprint in the map",
       {"bilinear", "trilinear"}},
      filterBiasParam(),
  };
  params.insert(params.end(), rest.begin(), rest.end());
  return params;
}

ParamSpec filterBiasParam() {
  return {"filter-bias", 1.5, 0, 10,
          "Receiver-plane bias: the receiver's depth slope times this many standard deviations of the filter"};
}

std::vector<ParamSpec> filteredMomentParams(const std::vector<ParamSpec>& extra) {
  std::vector<ParamSpec> params = shadowMapParams();
  for (const std::vector<ParamSpec>& more : {momentFilterParams(), extra})
    params.insert(params.end(), more.begin(), more.end());
  return params;
}

std::vector<ParamSpec> momentMapParams(const std::vector<ParamSpec>& extra) {
  std::vector<ParamSpec> params = filteredMomentParams(extra);
  params.push_back({"moment-storage",
                    kFp32,
                    0,
                    1,
                    "Moment storage: fp32, or fp16 (IEEE half: half the bytes for blur output, mips and lookups; "
                    "EVSM/ESM exponents clamped to 5.54)",
                    {"fp32", "fp16"}});
  return params;
}

MomentStorage momentStorage(const Params& params) {
  return params.getInt("moment-storage") == kFp16 ? MomentStorage::Float16 : MomentStorage::Float32;
}

ParamSpec bleedingParam() {
  return {"bleeding-reduction", 0, 0, 0.99,
          "Light-bleeding reduction: visibility below this amount becomes 0, the rest is rescaled; 0 = off"};
}

std::vector<ParamSpec> chebyshevParams() {
  return {{"min-variance", 1e-6, 0, 1, "Chebyshev minimum variance, in normalised light depth squared"},
          bleedingParam()};
}

Chebyshev Chebyshev::from(const Params& params) {
  Chebyshev c;
  if (params.has("min-variance")) c.minVariance = static_cast<float>(params.get("min-variance"));
  if (params.has("bleeding-reduction")) c.bleeding = static_cast<float>(params.get("bleeding-reduction"));
  return c;
}

MomentFilter MomentFilter::from(const Params& params, int mapSize) {
  MomentFilter filter{AutoRadius::from(params, "blur-radius"),
                      params.getInt("blur-filter") == kBox ? BlurFilter::Box : BlurFilter::Gaussian,
                      params.getInt("moment-filtering") == kTrilinear, static_cast<float>(params.get("filter-bias"))};
  if (params.isAuto("blur-radius-max")) filter.blur.max = std::max(kMinAutoBlurMax, mapSize / kBlurMaxDivisor);
  return filter;
}

MomentSettings MomentSettings::from(const Params& params, int mapSize) {
  MomentSettings m;
  m.map = MapSettings::from(params, mapSize);
  m.filter = MomentFilter::from(params, m.map.size);
  m.storage = momentStorage(params);
  m.chebyshev = Chebyshev::from(params);
  if (params.has("evsm-positive")) m.evsmPositive = static_cast<float>(params.get("evsm-positive"));
  if (params.has("evsm-negative")) m.evsmNegative = static_cast<float>(params.get("evsm-negative"));
  if (params.has("msm-bias")) m.msmBias = static_cast<float>(params.get("msm-bias"));
  if (params.has("esm-exponent")) {
    m.esmAuto = params.isAuto("esm-exponent");
    m.esmExponent = m.esmAuto ? 0.0 : params.get("esm-exponent");
    m.esmQuantile = params.get("esm-exponent-quantile");
    m.esmMin = params.get("esm-exponent-min");
    m.esmMax = params.get("esm-exponent-max");
  }
  return m;
}

MomentShade momentShade(const ShadowFrame& frame, const ShadowMap& map, const MapSettings& settings, float filterBias,
                        uint32_t channels) {
  MomentShade s{};
  s.width = static_cast<uint32_t>(frame.gbuffer.width);
  s.height = static_cast<uint32_t>(frame.gbuffer.height);
  s.channels = channels;
  s.levels = 1;
  s.depthNear = map.view.gpu.zNear;
  s.depthInvRange = 1.0f / (map.view.gpu.zFar - map.view.gpu.zNear);  // the moments stage's normalisation
  s.bias = settings.bias;
  s.slopeBias = settings.slopeBias;
  s.normalOffset = settings.normalOffset;
  s.filterWidth = s.maxWidth = 1.0f;
  s.filterBias = filterBias;
  return s;
}

void MomentDebug::allocate(Context& ctx, size_t pixels) {
  moments.allocate(ctx, pixels);
  stats.allocate(ctx, pixels);
}

void MomentDebug::addChannels(Context& ctx, Image& image, uint32_t channels, bool variance, bool width) const {
  const std::vector<cl_float4> m = moments.download(ctx);
  for (uint32_t c = 0; c < channels; ++c) {
    std::vector<float> channel(m.size());
    for (size_t i = 0; i < m.size(); ++i) channel[i] = m[i].s[c];
    image.add(fmt::format("moments.M{}", c + 1), std::move(channel));
  }
  const std::vector<cl_float2> st = stats.download(ctx);
  for (int c = 0; c < 2; ++c) {
    if (!(c == 0 ? variance : width)) continue;
    std::vector<float> channel(st.size());
    for (size_t i = 0; i < st.size(); ++i) channel[i] = st[i].s[c];
    image.add(c == 0 ? "variance.Y" : "filterWidth.Y", std::move(channel));
  }
}

void MomentTechnique::render(ShadowFrame& frame, Buffer<float>& visibility) {
  Context& ctx = frame.ctx;
  const MomentSettings& s = settings_;
  const int size = s.map.size;
  renderShadowMap(frame, s.map, map_, momentBlurReach(s.filter));
  blurRadius_ = resolveAutoRadius(frame, map_, s.map, s.filter.blur);
  channels_ = momentChannels(spec_.kind);
  MomentsConfig config;
  config.kind = spec_.kind;
  config.depthNear = map_.view.gpu.zNear;
  config.depthFar = map_.view.gpu.zFar;
  config.storage = s.storage;
  MomentShade shade = momentShade(frame, map_, s.map, s.filter.filterBias, channels_);
  if (spec_.configure) spec_.configure(frame, map_, s, config, shade);

  const ImageShape shape{static_cast<uint32_t>(size), static_cast<uint32_t>(size), channels_};
  filterMoments(ctx, config, shape);
  shade.levels = static_cast<uint32_t>(mipLevels_.size()) + 1;
  shade.blurSigma = momentBlurConfig(s.filter, blurRadius_).sigma;

  const GBuffer& g = frame.gbuffer;
  const size_t pixels = size_t(shade.width) * shade.height;
  debug_.allocate(ctx, pixels);
  Kernel kernel(ctx, spec_.source, spec_.entry, "shade", storageOptions(config.storage));
  const auto lookups = [&](const auto& moments, const auto& mips) {  // the storage in use (float or cl_half)
    kernel.args(g.position, g.normal, map_.gpu, moments, mips, mipLevels_, shade, visibility, debug_.moments,
                debug_.stats);
  };
  if (config.storage == MomentStorage::Float16)
    lookups(moments16_, mips16_);
  else
    lookups(moments_, mips_);
  kernel.moves(pixels * kVisibilityBytesPerPixel).launch(pixels, pixelGroup(frame.ctx));
}

void positiveWarpBlurMax(std::vector<ParamSpec>& params) {
  // Measured (docs/techniques/moments.md, "The blur radius from the scene's penumbrae"): the box on its floor at
  // 128x96 with a 512^2 map, whose penumbrae auto gives r = 3, has evsm2 leak 0.0034 at the contact line and put
  // light on 16 % of its umbra pixels (r = 2: 0.0006 and 6 %), esm 8 % (2 %); at 480x270 with 2048^2 maps their MAE
  // is lowest at r = 4-8 on box, staircase and stacked-planes and 1.2-2.6x higher at 16.
  paramNamed(params, "blur-radius-max").defaultValue = 2;
  // Their map keeps the filters' penumbra need (the narrowest tenth, not blurredPenumbraMapSize's fifth): a blur of at
  // most 2 texels draws a near-hard edge, placed better with every texel (scenes/default.json 640x360: the fifth's
  // smaller map raised esm's and evsm2's MAE 7-8 %).
}

BlurConfig momentBlurConfig(const MomentFilter& filter, int radius) {
  BlurConfig config;
  config.filter = filter.filter;
  config.radius = radius;
  config.sigma = static_cast<float>(std::sqrt(radius * (radius + 1.0) / 3.0));
  return config;
}

float momentBlurReach(const MomentFilter& filter) {
  // Under auto the map is fitted before its penumbrae are measured: the largest radius's reach.
  const int radius = filter.blur.limit();
  if (radius == 0) return 0.0f;
  const BlurConfig config = momentBlurConfig(filter, radius);
  return config.filter == BlurFilter::Box ? static_cast<float>(config.radius) : std::ceil(3.0f * config.sigma);
}

std::function<std::unique_ptr<Technique>(const Params&, int)> momentTechniqueFactory(MomentTechniqueSpec spec) {
  return [spec](const Params& params, int mapSize) {
    return std::make_unique<MomentTechnique>(spec, MomentSettings::from(params, mapSize));
  };
}

// The moments in the storage asked for; the buffers of the other storage are emptied.
void MomentTechnique::filterMoments(Context& ctx, const MomentsConfig& config, const ImageShape& shape) {
  if (config.storage == MomentStorage::Float16) {
    moments_.allocate(ctx, 0), mips_.allocate(ctx, 0);
    filterMomentsInto(ctx, config, shape, moments16_, mips16_);
  } else {
    moments16_.allocate(ctx, 0), mips16_.allocate(ctx, 0);
    filterMomentsInto(ctx, config, shape, moments_, mips_);
  }
}

// The moments, blurred if asked for (the moments stage fused into the blur's first pass), then the mip chain
// if asked for.
template <class T>
void MomentTechnique::filterMomentsInto(Context& ctx, const MomentsConfig& config, const ImageShape& shape,
                                        Buffer<T>& moments, Buffer<T>& mips) {
  moments.allocate(ctx, shape.count());
  if (blurRadius_ > 0) {
    const BlurConfig blur = momentBlurConfig(settings_.filter, blurRadius_);
    scratch_.allocate(ctx, blurMomentsScratch(ctx, shape, blur, config.storage, config.kind));
    blurMoments(ctx, map_.targets.depth, config, moments, scratch_, shape.width, shape.height, blur);
  } else {
    computeMoments(ctx, map_.targets.depth, shape.width, shape.height, config, moments);
  }
  if (!settings_.filter.trilinear) {
    mips.allocate(ctx, 0);  // no levels: the kernel takes the buffers either way (one element each)
    mipLevels_.allocate(ctx, 0, CL_MEM_READ_ONLY);
    return;
  }
  const PyramidLayout layout = pyramidLayout(shape.width, shape.height, 1);
  mips.allocate(ctx, layout.texels * shape.channels);
  // ESM's form (and clamped exponent) as the moments stage took them.
  const MomentsParams stage = momentsParams(config, shape.width, shape.height);
  if (config.kind == MomentKind::Esm && stage.esmLogSpace)
    computeLogMomentMips(ctx, moments, shape, mips, stage.expPositive);
  else
    computeMomentMips(ctx, moments, shape, mips);
  mipLevels_.allocate(ctx, layout.levels.size(), CL_MEM_READ_ONLY);
  mipLevels_.upload(ctx, std::span<const PyramidLevel>(layout.levels));
}

void MomentTechnique::addDebugChannels(Context& ctx, Image& image) {
  const uint32_t shown = spec_.debugMoments == 0 ? channels_ : spec_.debugMoments;
  debug_.addChannels(ctx, image, shown, spec_.hasVariance, settings_.filter.trilinear);
}

}  // namespace penumbra
