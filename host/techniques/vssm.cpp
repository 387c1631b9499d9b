// `vssm`: variance soft shadow mapping (Yang et al., PG 2010) with kernel subdivision: shadow map -> VSM moments
// -> SAT and min-max HSM (vssm_maps.h) -> kernels/vssm.cl per pixel. Debug channels: blocker depth, penumbra
// width, sub-kernels visited and the path each pixel took.
#include "host/techniques/vssm.h"

#include <fmt/format.h>

#include <cmath>

#include "host/techniques/registry.h"
#include "host/techniques/shadow_map.h"
#include "host/techniques/vssm_maps.h"
#include "kernels/shared/id_buffer.h"

namespace penumbra {
namespace {

enum Subdivision { kNone = 0, kUniform = 1, kAdaptive = 2, kMixed = 3 };
constexpr int kMaxAutoSatReduce = 8;
constexpr uint32_t kSearchNarrowings = 2;  // vssm-search adaptive: as pcss's PCSS_ADAPTIVE_STEPS

struct VssmTechniqueSettings {
  MapSettings map;
  VssmSettings vssm;
  static VssmTechniqueSettings from(const Params& params, int mapSize) {
    return {MapSettings::from(params, mapSize), VssmSettings::from(params)};
  }
  bool operator==(const VssmTechniqueSettings&) const = default;
};

class VarianceSoftShadows final : public TechniqueOf<VssmTechniqueSettings> {
 public:
  using TechniqueOf::TechniqueOf;

  void render(ShadowFrame& frame, Buffer<float>& visibility) override {
    VssmMapConfig config = settings_.vssm.maps;
    map_.casterTiles = settings_.vssm.castersHsm;  // the moments keep the receivers; the HSM the casters (below)
    // With the window around the casters (below), the receivers beyond it are never read: the map draws them only
    // within its reach at the widest blocks, plus one block of the window's alignment. The fitted near plane lies in
    // front of every caster (the moments' is tightened to the nearest below), so its widest kernel is at least theirs.
    const bool window = settings_.vssm.castersHsm && settings_.vssm.castersWindow;
    const uint32_t widestBlock = settings_.vssm.satReduceAuto ? kMaxAutoSatReduce : config.satReduce;
    map_.receiverReach = [window, widestBlock, maxRadius = config.maxRadius](const LightViewGpu& fitted) {
      return window ? static_cast<int>(vssmWindowReach(vssmWidestKernel(fitted, maxRadius), widestBlock) + widestBlock)
                    : -1;
    };
    renderShadowMap(frame, settings_.map, map_, config.maxRadius, MapNear::Fitted);
    const LightViewGpu& lv = map_.view.gpu;
    const auto width = static_cast<uint32_t>(lv.width), height = static_cast<uint32_t>(lv.height);
    // The HSM first, of the casters (--vssm-hsm casters): the tiles no caster reaches hold only receivers (a ground
    // under everything), which can block no light, and its tests read them as empty. Its top is the nearest caster
    // drawn, which the moments are normalised from (receivers nearer the light than every caster are lit: t < 0).
    const Buffer<uint32_t>* casterFree = map_.targets.casterFreeTiles(width, height);
    const cl_float2 drawn = maps_.buildHsm(frame.ctx, map_.targets.depth, width, height, casterFree);
    tightenMapNear(frame, settings_.map, map_, drawn.s[0]);
    if (settings_.vssm.satReduceAuto) config.satReduce = autoSatReduce(frame);
    // The moments and their SAT around the casters only (--vssm-sat-window casters, with the HSM of the casters):
    // vssmWindowReach around the tiles a caster reaches.
    if (window && casterFree != nullptr) {
      const uint32_t reach = vssmWindowReach(vssmWidestKernel(lv, config.maxRadius), config.satReduce);
      config.window = vssmCastersWindow(map_.targets.casterBox, width, height, reach, config.satReduce);
      frame.attributes["penumbra:vssm-sat-window"] = fmt::format(
          "{}x{} texels at ({}, {}) of the {}x{} map: its casters and {} texels around them", config.window.width,
          config.window.height, config.window.x, config.window.y, width, height, reach);
    }
    maps_.buildMoments(frame.ctx, map_.targets.depth, width, height, lv.zNear, lv.zFar, config);
    const VssmParams shade = vssmParams(settings_.vssm, maps_, frame.scene.bounds().radius());
    const GBuffer& g = frame.gbuffer;
    const uint32_t count = static_cast<uint32_t>(g.width) * static_cast<uint32_t>(g.height);
    debug_.allocate(frame.ctx, count);
    const ShadeFrame frameShade = shadeFrame(frame, settings_.map, 0, ID_BUFFER_OFF);  // no receiver plane, no ID buffer
    Kernel kernel(frame.ctx, "kernels/vssm.cl", "vssm_visibility", "shade", maps_.buildOptions());
    std::visit(
        [&](const auto& sat) {
          kernel
              .args(g.position, g.normal, map_.targets.depth, map_.gpu, frameShade, sat, maps_.satDesc(),
                    maps_.satOffset(), maps_.hsm(), maps_.levels(), maps_.nodes(), maps_.diskStrips(), shade, debug_,
                    visibility)
              .moves(uint64_t{count} * kVisibilityBytesPerPixel)
              .launch(count, pixelGroup(frame.ctx));
        },
        maps_.sat());
  }

  void addDebugChannels(Context& ctx, Image& image) override {
    const std::vector<cl_float4> debug = debug_.download(ctx);
    const char* names[] = {"blocker.Z", "penumbra.Z", "subkernels.Z", "path.Z"};
    for (int c = 0; c < 4; ++c) {
      std::vector<float> channel(debug.size());
      for (size_t i = 0; i < debug.size(); ++i) channel[i] = debug[i].s[c];
      image.add(names[c], std::move(channel));
    }
  }

 private:
  // --vssm-sat-reduce auto: the largest power of two up to kMaxAutoSatReduce at which the penumbra half-width that
  // vssm-sat-quantile of the shadowed pixels reach spans vssm-sat-penumbra SAT texels; recorded in the header.
  uint32_t autoSatReduce(ShadowFrame& frame) const {
    const double blocksAcross = settings_.vssm.satPenumbra;
    auto largestReduce = [blocksAcross](double halfWidth) {
      int reduce = 1;
      while (reduce < kMaxAutoSatReduce && halfWidth >= 2.0 * reduce * blocksAcross) reduce *= 2;
      return reduce;
    };
    return static_cast<uint32_t>(chooseFromPenumbra(frame, map_.targets.depth, map_.gpu, settings_.map.receiverBias(),
                                                    settings_.vssm.satQuantile, "vssm-sat-reduce", largestReduce));
  }

  ShadowMap map_;
  VssmMaps maps_;
  Buffer<cl_float4> debug_;
};

}  // namespace

VssmSettings VssmSettings::from(const Params& params) {
  VssmSettings s;
  s.maps.sat = static_cast<VssmSatMode>(params.getInt("vssm-sat"));
  s.maps.maxRadius = static_cast<float>(params.get("vssm-max-radius"));
  s.maps.treeHeight = static_cast<uint32_t>(params.getInt("vssm-levels"));
  s.subdivision = params.getInt("vssm-subdivision");
  s.searchDivisions = static_cast<uint32_t>(params.getInt("vssm-m"));
  s.shadeDivisions = static_cast<uint32_t>(params.getInt("vssm-n"));
  s.leafTaps = static_cast<uint32_t>(params.getInt("vssm-leaf-taps"));
  s.diskStrips = static_cast<uint32_t>(params.getInt("vssm-disk-strips"));
  s.litThreshold = params.get("vssm-lit-threshold");
  s.contact = params.get("vssm-contact");
  s.minVariance = static_cast<float>(params.get("vssm-min-variance"));
  s.pGuard = static_cast<float>(params.get("vssm-p-guard"));
  s.stackedSpread = static_cast<float>(params.get("vssm-stacked"));
  s.stackedTaps = static_cast<uint32_t>(params.getInt("vssm-stacked-taps"));
  s.stackedTrace = params.getInt("vssm-stacked-trace") == 1;
  s.firstMoment = params.getInt("vssm-first-moment") == 1;
  s.tiltShare = static_cast<float>(params.get("vssm-tilt"));
  s.castersHsm = params.getInt("vssm-hsm") == 1;
  s.castersWindow = params.getInt("vssm-sat-window") == 1;
  s.searchNarrowings = params.getInt("vssm-search") == kSearchAdaptive ? kSearchNarrowings : 0;
  s.satReduceAuto = params.isAuto("vssm-sat-reduce");
  s.maps.satReduce = s.satReduceAuto ? 1 : static_cast<uint32_t>(params.getInt("vssm-sat-reduce"));
  s.satPenumbra = params.get("vssm-sat-penumbra");
  s.satQuantile = params.get("vssm-sat-quantile");
  return s;
}

VssmParams vssmParams(const VssmSettings& settings, const VssmMaps& maps, float sceneRadius) {
  VssmParams p{};
  p.depthNear = maps.depthNear();
  p.depthInvRange = maps.depthInvRange();
  // Sec. 6.5 compares sigma^2 with 0.0001 r. A variance is a squared depth, so we read the threshold as
  // (0.0001 r) * r: identical for r = 1 and independent of the scene's scale. Normalised like the moments.
  const double r = sceneRadius, inv = p.depthInvRange;
  p.litVariance = static_cast<float>(settings.litThreshold * r * r * inv * inv);
  p.contactDepth = static_cast<float>(settings.contact * r);  // sec. 6.4: epsilon = 0.01 r
  p.maxRadius = settings.maps.maxRadius;
  p.minVariance = settings.minVariance;
  const int scheme = settings.subdivision;
  p.searchScheme = scheme == kNone       ? VSSM_SCHEME_NONE
                   : scheme == kAdaptive ? VSSM_SCHEME_ADAPTIVE
                                         : VSSM_SCHEME_UNIFORM;
  p.shadeScheme = scheme == kNone ? VSSM_SCHEME_NONE : scheme == kUniform ? VSSM_SCHEME_UNIFORM : VSSM_SCHEME_ADAPTIVE;
  p.searchDivisions = settings.searchDivisions;
  p.shadeDivisions = settings.shadeDivisions;
  p.leafTaps = settings.leafTaps;
  p.nodeCount = maps.nodeCount();
  p.pyramidLevels = maps.levelCount();
  p.planarMaxLit = settings.pGuard;
  p.diskStrips = settings.diskStrips;
  p.stackedSpread = settings.stackedSpread;
  p.stackedTaps = settings.stackedTaps;
  p.stackedTrace = settings.stackedTrace ? 1u : 0u;
  p.firstMoment = settings.firstMoment ? 1u : 0u;
  p.tiltShare = settings.tiltShare;
  p.searchNarrowings = settings.searchNarrowings;
  p.satReduce = maps.satReduce();
  p.satX = maps.window().x, p.satY = maps.window().y;
  p.satWidth = maps.window().width, p.satHeight = maps.window().height;
  return p;
}

std::vector<ParamSpec> vssmParamSpecs() {
  std::vector<ParamSpec> specs = {
      {"vssm-subdivision",
       kMixed,
       0,
       3,
       "Non-planarity kernels: none (lit, as SAVSM), uniform (m x m search, n x n shading), adaptive (quad-tree of "
       "height H for both) or mixed (uniform search, adaptive shading; the paper's choice)",
       {"none", "uniform", "adaptive", "mixed"}},
      {"vssm-m", 5, 1, 16,
       "Uniform blocker-search subdivision: m x m sub-kernels (at most ceil(2w / leaf taps) a side for a kernel of "
       "half-width w texels)"},
      {"vssm-n", 8, 1, 16,
       "Uniform shading subdivision: n x n sub-kernels (at most ceil(2w / leaf taps) a side for a kernel of "
       "half-width w texels)"},
      {"vssm-levels", 3, 1, VSSM_MAX_LEVELS,
       "Adaptive subdivision: quad-tree height H (up to 4^H leaf sub-kernels; at most floor(log2(2w / leaf taps)) "
       "levels for a kernel of half-width w texels)"},
      {"vssm-leaf-taps", 2, 1, 8, "PCF taps per side in a non-planarity leaf sub-kernel"},
      {"vssm-lit-threshold", 1e-4, 0, 1,
       "Fully-lit sub-kernel threshold: sigma^2 < threshold * r^2, r the scene's bounding-sphere radius"},
      {"vssm-contact", 0.01, 0, 1, "Contact shadows: 3x3 jittered PCF where d - z_occ < contact * r; 0 = off"},
      {"vssm-max-radius", 128, 1, 4096, "Largest blocker-search / penumbra half-width in texels"},
      {"vssm-p-guard", 0.9, 0, 1,
       "Eq. 4 divides by 1 - P: a search kernel whose Chebyshev P exceeds this is subdivided; 1 = only z_avg >= t"},
      {"vssm-min-variance", 1e-6, 0, 1, "Chebyshev minimum variance, in normalised light depth squared"},
      {"vssm-disk-strips", 8, 0, VSSM_MAX_DISK_STRIPS,
       "Beyond the paper: search and penumbra kernels as disks of at most this many area-matched SAT strips (one per "
       "texel row at most); 0 = the paper's squares"},
      {"vssm-search",
       kSearchAdaptive,
       0,
       1,
       "Blocker-search kernel: the light's cone cut at the near plane (full, the paper's L7), or narrowed twice by the "
       "nearest texel in it from the min-max HSM (adaptive, as --pcss-search)",
       {"full", "adaptive"}},
      {"vssm-stacked", 0.1, 0, 1,
       "Beyond the paper: a search or penumbra kernel whose eq. 4 blocker lies more than this share of the way from "
       "its nearest texel to the receiver holds blockers at several depths and is sampled by jittered taps (the "
       "blockers' mean depth, PCF); 0 = never"},
      {"vssm-stacked-taps", 8, 1, 32, "Stacked-blocker kernels: taps x taps jittered cells"},
      {"vssm-stacked-trace",
       1,
       0,
       1,
       "Beyond the paper: a receiver whose search kernel holds blockers at several depths also traces its segments to "
       "32 points of the light through the depth map, and keeps the darker of the two (occluders stacked inside the "
       "kernel fuse, where the blocker average lets light into the umbra)",
       {"off", "on"}},
      {"vssm-first-moment",
       1,
       0,
       1,
       "Beyond the paper: a shading kernel's lit share is the smaller of Chebyshev's bound and its first moment's "
       "share with the blocker search's depth (blockers there on average, the rest at the receiver or behind: also an "
       "upper bound), which Chebyshev's overestimates where the blockers spread in depth (off: Chebyshev's alone, the "
       "paper's)",
       {"off", "on"}},
      {"vssm-tilt", 0.05, 0, 16,
       "Beyond the paper: a planar penumbra kernel (its mean in front of the receiver) across which the receiver's own "
       "plane moves (its slope-scaled bias per texel times the half-width) by more than this share of the gap between "
       "the blocker depth and the receiver is filtered by jittered taps with the slope-scaled bias, not by Chebyshev's "
       "bound, which reads one receiver depth; 0 = never"},
      {"vssm-hsm",
       1,
       0,
       1,
       "Beyond the paper: the min-max HSM of the whole map (all, the paper's) or of the casters alone (casters: the "
       "rasterizer's tiles that no caster reaches read as empty, so a receiver that shadows nothing, such as a ground "
       "tilted to the light, fails no lit test)",
       {"all", "casters"}},
      {"vssm-sat-window",
       1,
       0,
       1,
       "Beyond the paper: the moments and their SAT over the whole map (map) or, with --vssm-hsm casters, over the "
       "window that holds the casters and the widest kernel around them (casters: the same images, fewer texels)",
       {"map", "casters"}},
      {"vssm-sat", 0, 0, 3, "SAT storage of the moments", {"fixed64", "fixed32", "fp32", "fp64"}},
  };
  ParamSpec reduce{"vssm-sat-reduce", 0, 1, 16,
                   "Beyond the paper: the moments and their SAT over blocks of N x N map texels (wide kernels read "
                   "block means; the HSM, contact and leaf PCF keep the map); 1 = the paper's; auto: the largest power "
                   "of two up to 8 at which the narrow end of the penumbrae (--vssm-sat-quantile) spans "
                   "--vssm-sat-penumbra blocks"};
  reduce.autoName = "auto";
  reduce.autoValue = 0;
  specs.push_back(std::move(reduce));
  specs.push_back({"vssm-sat-penumbra", 6, 1, 1024,
                   "--vssm-sat-reduce auto: SAT texels across the penumbra half-width --vssm-sat-quantile reaches"});
  specs.push_back(
      {"vssm-sat-quantile", 0.2, 0.01, 1,
       "--vssm-sat-reduce auto: the share of the shadowed pixels whose penumbra may span fewer SAT texels"});
  return specs;
}

TechniqueInfo vssmTechnique() {
  std::vector<ParamSpec> params = shadowMapParams();
  // Its error keeps falling until the narrow end of the penumbrae spans ~24 texels (its disk strips and sub-kernels are
  // whole texels): docs/techniques/README.md, "Beyond the pixels".
  paramNamed(params, "map-size-penumbra").defaultValue = 24;
  for (ParamSpec& spec : vssmParamSpecs()) params.push_back(std::move(spec));
  TechniqueInfo info{"vssm",
                     "Variance soft shadow mapping (SAT moments, min-max HSM, kernel subdivision) for area lights",
                     params, makeTechnique<VarianceSoftShadows>};
  info.kernelReach = [](const Params& p, int) { return p.get("vssm-max-radius"); };  // at any map size
  return info;
}

}  // namespace penumbra
