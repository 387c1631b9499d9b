// Split planning, per-split light views, device constants and AOVs for pssm and psvsm.
#include "host/techniques/split_maps.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <span>
#include <stdexcept>

#include "host/cl/kernel.h"

namespace penumbra {
namespace {

enum SplitCountChoice { kAutoSplits = 0 };  // choice k > 0 is k splits
enum SnapChoice { kSnapOff = 0, kSnapOn = 1 };

std::vector<std::string> splitCountChoices() {
  std::vector<std::string> choices = {"auto"};
  for (int k = 1; k <= PSSM_MAX_SPLITS; ++k) choices.push_back(std::to_string(k));
  return choices;
}

// World width of one texel of `view` (spot: at the light depth `depth`).
float texelWorld(const LightView& view, float depth) {
  return view.gpu.kind == LIGHT_KIND_SPOT ? view.gpu.texelScale * depth : view.gpu.texelScale;
}

struct SplitFit {
  const ShadowFrame& frame;
  const WarpSettings& warp;
  ReceiverBounds receivers;  // what splits are cropped to: the visible receivers, or everything (fit=scene)
  glm::mat4 lightEye;
  int size;
  float margin;
  bool snap;

  // The split's view; with --warp lispsm its own LiSPSM warp, n from the split's near/far (Luksch sec. 7.1).
  LightView view(float near, float far, LispsmFit* lispsm = nullptr) const {
    const ReceiverBounds box = sliceBounds(frame.light, lightEye, frustumSliceCorners(frame.camera, near, far), receivers);
    const ReceiverBounds* crop = box.empty ? &frame.receivers : &box;
    if (warp.lispsm) return fitWarpedLightView(frame, warp, size, margin, near, far, crop, lispsm);
    return fitLightView(frame.light, frame.scene.bounds(), size, crop, margin, snap);
  }
};

// Luksch sec. 7.2 with eq. 12's width measured: sigma is the far split's light-space width (the map's world extent,
// margin included) over the camera's width 2 d tan(alpha / 2) at its far plane d, from a first guess sigma = 1. Eq.
// 15's smRes is the map's size, or under --map-size auto the larger size the pixels alone ask for (ShadowFrame's
// pixelsMapSize): where the penumbrae cap the map below it, more texels per pixel buy nothing, so neither do splits.
float autoFactor(const SplitFit& fit, float near, float far, float rho, std::string& how) {
  const int resolution = std::max(fit.size, fit.frame.pixelsMapSize);
  const Camera& camera = fit.frame.camera;
  const float res = static_cast<float>(camera.width);
  // The camera's width per unit depth at the far plane (an orthographic camera's width is the same at every depth).
  const float widthPerDepth = 2.0f * camera.halfExtentAt(far).x / far;
  float factor = optimalTilingFactor(res, 1.0f, rho, resolution), sigma = 1.0f;
  if (factor < 1.0f) {
    const LightView last = fit.view(std::max(near, factor * far), far);
    const float depth = fit.frame.light.type == LightType::Spot ? last.gpu.zFar : 0.0f;
    sigma = std::max(texelWorld(last, depth) * static_cast<float>(fit.size) / (widthPerDepth * far), 1e-3f);
    factor = optimalTilingFactor(res, sigma, rho, resolution);
  }
  how = fmt::format("auto (eq. 15 factor {:.4g}, sigma {:.4g}, rho {:.4g}, smRes {})", factor, sigma, rho, resolution);
  return factor;
}

}  // namespace

std::string splitsCallerMapRefusal() {
  return "it draws one map per split of the camera's depth range, each cropped to its slice of the view frustum "
         "(Zhang et al. 2006); a caller's single map has no splits";
}

std::vector<ParamSpec> splitParams() {
  return {
      {"pssm-splits", 0, 0, PSSM_MAX_SPLITS,
       "Parallel splits: a count, or auto (Luksch's optimal tiling up to --pssm-max-splits)", splitCountChoices()},
      {"pssm-scheme", static_cast<double>(SplitScheme::Practical), 0, 2, "Split distances for a fixed count",
       {"uniform", "logarithmic", "practical"}},
      {"pssm-lambda", 0.75, 0, 1, "Practical scheme: lambda C_log + (1 - lambda) C_uniform (1 = logarithmic)"},
      {"pssm-max-splits", 8, 1, PSSM_MAX_SPLITS, "Most splits the auto scheme may use"},
      {"pssm-rho", 1.0, 0.05, 16, "Auto scheme: pixels per shadow-map texel allowed at a split's near plane"},
      {"pssm-snap", kSnapOff, 0, 1, "Snap each split's map to whole texels (stable under camera motion)",
       {"off", "on"}},
      {"pssm-blend", 0.0, 0, 0.5, "Blend band: fraction of a split's depth range faded into the next; 0 = off"},
      {"pssm-split-bias", 0.0, -1e9, 1e9,
       "Luksch eq. 10's delta_bias: every inner split plane moved by this view depth (kept ordered); 0 = off"},
  };
}

namespace {
SplitFit splitFit(const ShadowFrame& frame, const MapSettings& map, float marginTexels, bool snap) {
  ReceiverBounds everything;
  everything.empty = false;
  everything.lo = glm::vec2(-INFINITY), everything.hi = glm::vec2(INFINITY);
  everything.depthMax = INFINITY;
  return {frame,    map.fit.warp, map.fit.fitReceivers ? frame.receivers : everything,
          lightEyeMatrix(frame.light, frame.scene.bounds()), map.size, marginTexels, snap};
}
}  // namespace

SplitSettings SplitSettings::from(const Params& params) {
  SplitSettings s;
  s.count = params.getInt("pssm-splits");
  s.scheme = static_cast<SplitScheme>(params.getInt("pssm-scheme"));
  s.lambda = static_cast<float>(params.get("pssm-lambda"));
  s.maxSplits = params.getInt("pssm-max-splits");
  s.rho = static_cast<float>(params.get("pssm-rho"));
  s.snap = params.getInt("pssm-snap") == kSnapOn;
  s.blend = static_cast<float>(params.get("pssm-blend"));
  s.splitBias = static_cast<float>(params.get("pssm-split-bias"));
  if (s.snap && WarpSettings::from(params).lispsm)
    throw std::invalid_argument("--pssm-snap on cannot be combined with --warp lispsm");
  return s;
}

LightView sliceLightView(const ShadowFrame& frame, const MapSettings& map, float near, float far, float marginTexels) {
  return splitFit(frame, map, marginTexels, false).view(near, far);
}

SplitPlan planSplits(ShadowFrame& frame, const MapSettings& map, const SplitSettings& splits, float marginTexels) {
  SplitPlan plan;
  plan.warpOption = map.fit.warp.declared;
  const SplitFit fit = splitFit(frame, map, marginTexels, splits.snap);
  const auto [near, far] = tightViewDepth(frame.ctx, frame.gbuffer);
  const int count = splits.count;
  const float lambda = splits.lambda;
  if (count == kAutoSplits) {
    const float factor = autoFactor(fit, near, far, splits.rho, plan.scheme);
    plan.distances = autoSplitDistances(near, far, factor, splits.maxSplits, lambda);
  } else {
    const SplitScheme scheme = splits.scheme;
    plan.distances = splitDistances(scheme, count, near, far, lambda);
    static const char* kNames[] = {"uniform", "logarithmic", "practical"};
    plan.scheme = fmt::format("{}{}", kNames[static_cast<int>(scheme)],
                              scheme == SplitScheme::Practical ? fmt::format(" (lambda {})", lambda) : "");
  }
  const float delta = splits.splitBias;
  biasSplitDistances(plan.distances, delta);
  if (delta != 0.0f) plan.scheme += fmt::format(", delta_bias {}", delta);
  for (size_t s = 0; s + 1 < plan.distances.size(); ++s) {
    LispsmFit warp;
    plan.views.push_back(fit.view(plan.distances[s], plan.distances[s + 1], &warp));
    if (map.fit.warp.lispsm) plan.warps.push_back(warp);
  }
  return plan;
}

void SplitGpu::upload(Context& ctx, const ShadowFrame& frame, const SplitPlan& plan, const MapSettings& map,
                      const SplitSettings& splitSettings, float blurSigma) {
  const size_t m = plan.views.size();
  std::vector<LightViewGpu> gpu;
  host.assign(m, PssmSplit{});
  for (size_t s = 0; s < m; ++s) {
    const LightViewGpu& v = plan.views[s].gpu;
    gpu.push_back(v);
    PssmSplit& split = host[s];
    split.nearDistance = plan.distances[s];
    split.farDistance = plan.distances[s + 1];
    // Lauritzen step 2d: filter sizes scale with the zoom; texel sizes compared per unit depth for spot lights.
    split.filterScale = plan.views[0].gpu.texelScale / v.texelScale;
    split.blurSigma = blurSigma * split.filterScale;
    split.depthNear = v.zNear;
    split.depthInvRange = 1.0f / (v.zFar - v.zNear);
  }
  const int size = map.size;
  shade = PssmShade{};
  shade.width = static_cast<uint32_t>(frame.gbuffer.width);
  shade.height = static_cast<uint32_t>(frame.gbuffer.height);
  shade.splits = static_cast<uint32_t>(m);
  shade.mapTexels = static_cast<uint32_t>(size) * static_cast<uint32_t>(size);
  shade.blend = splitSettings.blend;
  shade.bias = map.bias, shade.slopeBias = map.slopeBias, shade.normalOffset = map.normalOffset;
  views.allocate(ctx, m, CL_MEM_READ_ONLY);
  views.upload(ctx, std::span<const LightViewGpu>(gpu));
  splits.allocate(ctx, m, CL_MEM_READ_ONLY);
  splits.upload(ctx, std::span<const PssmSplit>(host));
}

void SplitAovs::allocate(Context& ctx, size_t pixels) {
  split.allocate(ctx, pixels);
  resolutionError.allocate(ctx, pixels);
}

void SplitAovs::addChannels(Context& ctx, Image& image) const {
  image.add("split.Y", split.download(ctx));
  image.add("resolutionError.Y", resolutionError.download(ctx));
}

namespace {
Buffer<LightViewGpu> splitZero(ShadowFrame& frame, const SplitPlan& plan) {
  return Buffer<LightViewGpu>(frame.ctx, std::span<const LightViewGpu>(&plan.views[0].gpu, 1), CL_MEM_READ_ONLY);
}
}  // namespace

int resolveAutoRadiusOnSplit0(ShadowFrame& frame, const SplitPlan& plan, const Buffer<float>& depth,
                              const MapSettings& map, const AutoRadius& radius) {
  if (!radius.automatic) return radius.radius;
  return resolveAutoRadius(frame, depth, splitZero(frame, plan), map.receiverBias(), radius);
}

AutoKernel resolveAutoKernelOnSplit0(ShadowFrame& frame, const SplitPlan& plan, const Buffer<float>& depth,
                                     const MapSettings& map, const AutoRadius& radius, float maxWidth) {
  if (!radius.automatic) return {radius.radius, static_cast<float>(radius.radius)};
  return resolveAutoKernel(frame, depth, splitZero(frame, plan), map.receiverBias(), radius, maxWidth);
}

void recordSplits(ShadowFrame& frame, const SplitPlan& plan) {
  std::string distances, fits;
  for (float d : plan.distances) distances += fmt::format("{}{:.6g}", distances.empty() ? "" : " ", d);
  for (const LightView& v : plan.views)
    fits += fmt::format("{}{}x{} texel {:.4g}{} depth {:.6g}..{:.6g}", fits.empty() ? "" : "; ", v.gpu.width,
                        v.gpu.height, v.gpu.texelScale, v.gpu.kind == LIGHT_KIND_SPOT ? "/depth" : "", v.gpu.zNear,
                        v.gpu.zFar);
  frame.attributes["penumbra:pssm-distances"] = distances;
  frame.attributes["penumbra:pssm-scheme"] = fmt::format("{}, {} splits", plan.scheme, plan.views.size());
  frame.attributes["penumbra:light-fit"] = fits;
  if (!plan.warps.empty()) {
    std::string warps;
    for (const LispsmFit& w : plan.warps) warps += fmt::format("{}{}", warps.empty() ? "" : "; ", w.describe());
    frame.attributes["penumbra:warp"] = warps;
  } else if (plan.warpOption) {
    frame.attributes["penumbra:warp"] = "none";
  }
}

}  // namespace penumbra
