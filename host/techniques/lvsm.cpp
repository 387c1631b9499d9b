// `lvsm`: layered variance shadow maps (Lauritzen & McCool, GI 2008). Plans the splits (uniform, manual, or
// Lloyd relaxation, sec. 4; optionally the layer count from the leak metric), then per layer: the eq. 6
// warped moments (host/stages/moments.h), blur and mips, stored fp32 or 16-bit unorm (sec. 5); then one
// lookup per pixel in the receiver's layer (kernels/lvsm.cl). One layer is `vsm`.
#include <fmt/format.h>

#include <stdexcept>

#include "host/cl/kernel.h"
#include "host/stages/pyramid.h"
#include "host/techniques/lvsm_layers.h"
#include "host/techniques/moment_map.h"
#include "host/techniques/registry.h"

namespace penumbra {
namespace {

enum Placement { kUniform = 0, kManual = 1, kLloyd = 2 };
enum Storage { kFloat32 = 0, kUnorm16 = 1 };
enum Schedule { kEveryFrame = 0, kIncremental = 1 };

struct LvsmSettings {
  MapSettings map;
  MomentFilter filter;
  Chebyshev chebyshev;
  int layers = 0;  // lvsm-layers; 0 = auto
  Placement placement = kLloyd;
  std::vector<float> manual;  // lvsm-splits: interior splits, empty when not given
  float overlap = 0, transition = 0;
  bool unorm = false;  // lvsm-storage unorm16
  LloydConfig lloyd;   // lvsm-lloyd-iterations, -tolerance, lvsm-teleport
  bool incremental = false;  // lvsm-lloyd-schedule incremental
  int splitsPerFrame = 0;
  int maxLayers = 0;
  double autoGain = 0;
  float leakGap = 0;

  static LvsmSettings from(const Params& params, int mapSize) {
    LvsmSettings s;
    s.map = MapSettings::from(params, mapSize);
    s.filter = MomentFilter::from(params, s.map.size);
    s.chebyshev = Chebyshev::from(params);
    s.layers = params.getInt("lvsm-layers");
    s.placement = static_cast<Placement>(params.getInt("lvsm-placement"));
    s.overlap = static_cast<float>(params.get("lvsm-overlap"));
    s.transition = static_cast<float>(params.get("lvsm-transition"));
    s.unorm = params.getInt("lvsm-storage") == kUnorm16;
    s.lloyd.maxIterations = params.getInt("lvsm-lloyd-iterations");
    s.lloyd.tolerance = static_cast<float>(params.get("lvsm-lloyd-tolerance"));
    s.lloyd.teleport = params.getInt("lvsm-teleport") == 1;
    s.incremental = params.getInt("lvsm-lloyd-schedule") == kIncremental;
    s.splitsPerFrame = params.getInt("lvsm-lloyd-splits-per-frame");
    s.maxLayers = params.getInt("lvsm-max-layers");
    s.autoGain = params.get("lvsm-auto-gain");
    s.leakGap = static_cast<float>(params.get("lvsm-leak-gap"));
    if (params.get("lvsm-transition") > params.get("lvsm-overlap"))
      throw std::invalid_argument(fmt::format("--lvsm-transition {} is larger than --lvsm-overlap {}",
                                              params.get("lvsm-transition"), params.get("lvsm-overlap")));
    const std::string& text = params.getText("lvsm-splits");
    if (!text.empty()) s.manual = parseSplits(text);
    if (s.placement == kManual && text.empty())
      throw std::invalid_argument("--lvsm-placement manual needs --lvsm-splits");
    if (!text.empty() && (s.placement == kUniform || s.layers == 0))
      throw std::invalid_argument("--lvsm-splits applies to manual and lloyd placement with a fixed layer count");
    if (s.incremental && s.layers == 0)
      throw std::invalid_argument("--lvsm-lloyd-schedule incremental needs a fixed layer count (--lvsm-layers 1..16)");
    return s;
  }
  bool operator==(const LvsmSettings&) const = default;
};

class LayeredVsm final : public TechniqueOf<LvsmSettings> {
 public:
  using TechniqueOf::TechniqueOf;

  void render(ShadowFrame& frame, Buffer<float>& visibility) override;
  void addDebugChannels(Context& ctx, Image& image) override {
    debug_.addChannels(ctx, image, 2, true, settings_.filter.trilinear);
    image.add("layer.Y", layerIndex_.download(ctx));
  }

 private:
  std::vector<float> planSplits(ShadowFrame& frame, LvsmLayout& layout);
  // The header's record of the splits, the placement and the leak; returns `splits`.
  std::vector<float> recordSplits(ShadowFrame& frame, const std::vector<float>& splits, const LvsmLayout& layout,
                                  const std::string& how, const std::string& leaks) const;
  LvsmLayout layoutFor(const std::vector<float>& splits, bool uniform) const {
    return lvsmLayout(splits, uniform, settings_.overlap, settings_.transition, settings_.chebyshev.minVariance,
                      settings_.leakGap);
  }
  double leak(ShadowFrame& frame, const LvsmLayout& layout) const {
    const auto size = static_cast<uint32_t>(settings_.map.size);
    return lvsmLeak(frame.ctx, map_.targets.depth, size, size, map_.view.gpu.zNear, map_.view.gpu.zFar, layout);
  }
  void buildLayers(Context& ctx, const LvsmLayout& layout);

  LloydResult incrementalStep(ShadowFrame& frame, const LvsmSamples& samples, std::vector<float> start,
                              LloydConfig config);

  int blurRadius_ = 0;  // this frame's blur-radius (resolved under auto)
  std::vector<float> kept_;  // incremental schedule: the splits of the last frame, s_0..s_N
  size_t round_ = 0;         // incremental schedule: frames so far (which splits move next)
  ShadowMap map_;
  Buffer<float> moments_, scratch_, mips_, layers_, layerMips_;
  Buffer<cl_ushort> layers16_, layerMips16_;
  Buffer<PyramidLevel> mipLevels_;
  Buffer<float> layerIndex_;
  MomentDebug debug_;
  size_t planeFloats_ = 0, mipFloats_ = 0;
};

// Splits by the placement parameter; with --lvsm-layers 0 the layer count grows while the leak metric drops
// by at least --lvsm-auto-gain (relative) and is above 1e-4.
std::vector<float> LayeredVsm::planSplits(ShadowFrame& frame, LvsmLayout& layout) {
  const LvsmSettings& set = settings_;
  const Placement placement = set.placement;
  const int layers = set.layers;
  std::string how = "uniform", leaks;
  std::vector<float> splits = !set.manual.empty() ? set.manual : uniformSplits(std::max(layers, 1));
  if (placement == kManual) how = "manual";
  if (placement == kLloyd) {
    const auto size = static_cast<uint32_t>(set.map.size);
    LvsmSamples samples;
    lloydSamples(frame.ctx, map_.targets.depth, size, size, map_.view.gpu.zNear, map_.view.gpu.zFar,
                 set.chebyshev.minVariance, samples);
    const LloydConfig config = set.lloyd;
    if (set.incremental) {
      const LloydResult r = incrementalStep(frame, samples, splits, config);
      splits = r.splits;
      how = fmt::format("lloyd incremental frame={} splits-per-frame={} teleports={} last-move={:.3g}", round_,
                        set.splitsPerFrame, r.teleports, r.lastMove);
      layout = layoutFor(splits, false);
      return recordSplits(frame, splits, layout, how, leaks);
    }
    LloydResult r = lloydRelax(frame.ctx, samples, splits, config);
    if (layers == 0) {  // auto: N = 1, 2, ..., each started from N - 1's splits plus one in the heaviest layer
      const int maxLayers = set.maxLayers;
      r = LloydResult{uniformSplits(1)};
      double best = leak(frame, layoutFor(r.splits, false));
      leaks = fmt::format("N=1:{:.4g}", best);
      while (static_cast<int>(r.splits.size()) - 1 < maxLayers && best > 1e-4) {
        std::vector<float> start = r.splits;
        if (!splitHeaviestLayer(frame.ctx, samples, start)) break;
        LloydResult next = lloydRelax(frame.ctx, samples, start, config);
        const double value = leak(frame, layoutFor(next.splits, false));
        leaks += fmt::format(" N={}:{:.4g}", next.splits.size() - 1, value);
        if (value > (1.0 - set.autoGain) * best) break;
        r = next, best = value;
      }
    }
    splits = r.splits;
    how = fmt::format("lloyd iterations={} teleports={} last-move={:.3g} {}", r.iterations, r.teleports, r.lastMove,
                      r.converged ? "converged" : "stopped");
  }
  layout = layoutFor(splits, placement == kUniform);
  return recordSplits(frame, splits, layout, how, leaks);
}

// Sec. 5's schedule for sequences: one Lloyd step a frame that moves only --lvsm-lloyd-splits-per-frame splits
// (round-robin), started from the last frame's splits, which the technique keeps (the Renderer keeps the technique
// while its parameters stay the same), so the splits converge over frames rather than within each.
LloydResult LayeredVsm::incrementalStep(ShadowFrame& frame, const LvsmSamples& samples, std::vector<float> start,
                                        LloydConfig config) {
  if (kept_.size() == start.size()) start = kept_;
  config.maxIterations = 1;
  config.splitsPerIteration = settings_.splitsPerFrame;
  config.firstSplit = round_ * static_cast<size_t>(config.splitsPerIteration);
  LloydResult r = lloydRelax(frame.ctx, samples, start, config);
  kept_ = r.splits;
  ++round_;
  return r;
}

std::vector<float> LayeredVsm::recordSplits(ShadowFrame& frame, const std::vector<float>& splits,
                                            const LvsmLayout& layout, const std::string& how,
                                            const std::string& leaks) const {
  const double finalLeak = leak(frame, layout);
  frame.attributes["penumbra:lvsm-splits"] = formatSplits(splits);
  frame.attributes["penumbra:lvsm-placement"] = how;
  frame.attributes["penumbra:lvsm-leak"] =
      leaks.empty() ? fmt::format("{:.6g}", finalLeak) : fmt::format("{:.6g} ({})", finalLeak, leaks);
  std::string intervals;
  for (uint32_t i = 0; i < layout.count; ++i)
    intervals += fmt::format("{}[{:.6g},{:.6g}]", i ? " " : "", layout.layer[2 * i], layout.layer[2 * i + 1]);
  frame.attributes["penumbra:lvsm-layers"] = intervals;
  return splits;
}

// Per layer (sec. 5): warped moments, blur, mips, storage. fp32 layers are written in place, each stage
// straight into its layer's slice of the layer array (Buffer::region); unorm16 layers are packed from the fp32
// working buffers.
void LayeredVsm::buildLayers(Context& ctx, const LvsmLayout& layout) {
  const auto size = static_cast<uint32_t>(settings_.map.size);
  const ImageShape shape{size, size, 2};
  const bool trilinear = settings_.filter.trilinear, unorm = settings_.unorm;
  const bool blurred = blurRadius_ > 0;
  const PyramidLayout pyramid = pyramidLayout(size, size, 1);
  const size_t mipCount = trilinear ? pyramid.texels * 2 : 0;
  // Layer strides rounded up so that every layer's slice starts at an offset a sub-buffer may have.
  planeFloats_ = Buffer<float>::alignedCount(ctx, shape.count());
  mipFloats_ = Buffer<float>::alignedCount(ctx, mipCount);
  const size_t n = layout.count;
  moments_.allocate(ctx, unorm || blurred ? shape.count() : 0);
  scratch_.allocate(ctx, blurred ? shape.count() : 0);
  mips_.allocate(ctx, unorm ? mipCount : 0);
  layers_.allocate(ctx, unorm ? 0 : n * planeFloats_);
  layerMips_.allocate(ctx, unorm ? 0 : n * mipFloats_);
  layers16_.allocate(ctx, unorm ? n * planeFloats_ : 0);
  layerMips16_.allocate(ctx, unorm ? n * mipFloats_ : 0);
  mipLevels_.allocate(ctx, trilinear ? pyramid.levels.size() : 0, CL_MEM_READ_ONLY);
  if (trilinear) mipLevels_.upload(ctx, std::span<const PyramidLevel>(pyramid.levels));
  MomentsConfig config;
  config.kind = MomentKind::Lvsm;
  config.depthNear = map_.view.gpu.zNear;
  config.depthFar = map_.view.gpu.zFar;
  for (size_t i = 0; i < n; ++i) {
    config.layers = {{layout.layer[2 * i], layout.layer[2 * i + 1]}};
    Buffer<float> plane = unorm ? moments_ : layers_.region(ctx, i * planeFloats_, shape.count());
    if (blurred) {
      computeMoments(ctx, map_.targets.depth, size, size, config, moments_);
      blur(ctx, moments_, plane, scratch_, shape, momentBlurConfig(settings_.filter, blurRadius_));
    } else {
      computeMoments(ctx, map_.targets.depth, size, size, config, plane);
    }
    if (unorm) packMomentsUnorm16(ctx, plane, shape.count(), layers16_, i * planeFloats_);
    if (!trilinear) continue;
    Buffer<float> mips = unorm ? mips_ : layerMips_.region(ctx, i * mipFloats_, mipCount);
    computeMomentMips(ctx, plane, shape, mips);
    if (unorm) packMomentsUnorm16(ctx, mips, mipCount, layerMips16_, i * mipFloats_);
  }
}

void LayeredVsm::render(ShadowFrame& frame, Buffer<float>& visibility) {
  Context& ctx = frame.ctx;
  const LvsmSettings& set = settings_;
  renderShadowMap(frame, set.map, map_, momentBlurReach(set.filter));
  blurRadius_ = resolveAutoRadius(frame, map_, set.map, set.filter.blur);
  LvsmLayout layout;
  planSplits(frame, layout);
  buildLayers(ctx, layout);
  layout.planeFloats = static_cast<uint32_t>(planeFloats_);
  layout.mipFloats = static_cast<uint32_t>(mipFloats_);
  Buffer<LvsmLayout> layoutBuffer(ctx, std::span<const LvsmLayout>(&layout, 1), CL_MEM_READ_ONLY);

  MomentShade shade = momentShade(frame, map_, set.map, set.filter.filterBias, 2);
  set.chebyshev.apply(shade);
  shade.levels = static_cast<uint32_t>(mipLevels_.size()) + 1;
  shade.blurSigma = momentBlurConfig(set.filter, blurRadius_).sigma;
  const GBuffer& g = frame.gbuffer;
  const size_t pixels = size_t(shade.width) * shade.height;
  debug_.allocate(ctx, pixels);
  layerIndex_.allocate(ctx, pixels);
  const bool unorm = set.unorm;
  Kernel kernel(ctx, "kernels/lvsm.cl", "lvsm_visibility", "shade", unorm ? "-DLVSM_UNORM16" : "");
  if (unorm)
    kernel.args(g.position, g.normal, map_.gpu, layers16_, layerMips16_, mipLevels_, shade, layoutBuffer, visibility,
                debug_.moments, debug_.stats, layerIndex_);
  else
    kernel.args(g.position, g.normal, map_.gpu, layers_, layerMips_, mipLevels_, shade, layoutBuffer, visibility,
                debug_.moments, debug_.stats, layerIndex_);
  // G-buffer in, visibility, debug moments (16 B), stats (8 B) and layer index (4 B) out.
  kernel.moves(pixels * (kVisibilityBytesPerPixel + 16 + 8 + 4)).launch(pixels, pixelGroup(frame.ctx));
}

std::vector<ParamSpec> lvsmParams() {
  std::vector<ParamSpec> p = chebyshevParams();
  p.push_back({"lvsm-layers", 4, 0, MOMENTS_MAX_LAYERS, "LVSM layers N; 0 = auto (grow while the leak metric drops)"});
  p.push_back({"lvsm-placement", kLloyd, 0, 2, "LVSM split placement", {"uniform", "manual", "lloyd"}});
  p.push_back(textParam("lvsm-splits",
                        "LVSM interior splits in normalised light depth, e.g. 0.2,0.5 (sets N); manual placement, "
                        "or Lloyd's starting point"));
  p.push_back({"lvsm-overlap", 0.01, 0, 0.25, "LVSM layer overlap delta (normalised depth, sec. 3.4)"});
  p.push_back({"lvsm-transition", 0.005, 0, 0.25,
               "LVSM blend half-width around each split (normalised depth, <= overlap); 0 = off"});
  p.push_back({"lvsm-storage", kFloat32, 0, 1, "LVSM layer storage", {"float32", "unorm16"}});
  p.push_back({"lvsm-lloyd-iterations", 16, 1, 256, "Lloyd relaxation: most iterations"});
  p.push_back({"lvsm-lloyd-tolerance", 1e-3, 0, 1, "Lloyd relaxation: stop when no split moves farther"});
  p.push_back({"lvsm-teleport", 1, 0, 1, "Lloyd relaxation: teleport the splits of empty clusters", {"off", "on"}});
  p.push_back({"lvsm-lloyd-schedule",
               kEveryFrame,
               0,
               1,
               "Lloyd relaxation: to convergence every frame, or one step a frame from the last frame's splits "
               "(sec. 5, for sequences)",
               {"frame", "incremental"}});
  p.push_back({"lvsm-lloyd-splits-per-frame", 2, 1, MOMENTS_MAX_LAYERS - 1,
               "Incremental Lloyd schedule: splits moved per frame, round-robin (the paper's two)"});
  p.push_back({"lvsm-max-layers", 8, 1, MOMENTS_MAX_LAYERS, "Auto layer count: most layers"});
  p.push_back(
      {"lvsm-auto-gain", 0.25, 0, 1, "Auto layer count: keep a layer only if it cuts the leak by this fraction"});
  p.push_back({"lvsm-leak-gap", 0.05, 0.001, 1,
               "Leak metric: receiver distance behind the farthest occluder (normalised depth)"});
  return p;
}

}  // namespace

TechniqueInfo lvsmTechnique() {
  std::vector<ParamSpec> params = filteredMomentParams(lvsmParams());
  blurredPenumbraMapSize(params);
  return {"lvsm", "Layered variance shadow maps: the depth range split into warped VSM layers (Lloyd-placed)", params,
          makeTechnique<LayeredVsm>};
}

}  // namespace penumbra
