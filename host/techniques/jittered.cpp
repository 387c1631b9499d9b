// `jittered`: confidence-based jittered shadow maps (Luksch sec. 6; Scherzer et al. 2007). Pass 0 is sm's map;
// every further pass redraws it with a sub-texel translation from the Halton sequence (bases 2 and 3, sec. 6.1,
// Fig. 3) and optionally a rotation about the light axis (base 5), and kernels/jittered.cl keeps, per pixel, the
// result of the most confident lookup (simple / adapted / optimal, sec. 6.2-6.3). The stopping rule of sec. 6.3:
// stop once each of the last `jitter-window` passes changed the visibility of at most epsilon of the covered pixels
// (or, optimal, once at most epsilon are below the confidence they need), else after `jitter-passes`. Occlusion
// queries have no compute counterpart: the accumulation kernel counts with atomics and the host reads the counters
// once a pass. Each pass runs over the work list of pixels the previous one left changeable (two lists, swapped).
#include "kernels/shared/jittered.h"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <glm/gtc/matrix_transform.hpp>
#include <limits>
#include <optional>
#include <stdexcept>

#include "host/cl/kernel.h"
#include "host/techniques/registry.h"
#include "host/techniques/shadow_map.h"
#include "host/techniques/split_maps.h"
#include "host/techniques/warp.h"
#include "kernels/shared/id_buffer.h"
#include "raster/stages.h"

namespace penumbra {
namespace {

// The radical inverse of `index` in `base` (Halton 1960): 0, 1/2, 1/4, 3/4, ... for base 2.
double halton(uint32_t index, uint32_t base) {
  double result = 0.0, digit = 1.0 / base;
  for (; index > 0; index /= base, digit /= base) result += digit * (index % base);
  return result;
}

// Halton value shifted so that pass 0 gets 0: in [-0.5, 0.5).
float centred(uint32_t pass, uint32_t base) {
  const double h = halton(pass, base) + 0.5;
  return static_cast<float>(h - std::floor(h) - 0.5);
}

// ndc = a u + b of a separable map, u in its light eye's x/y units (perspective: u = x / -z, b = -P20; orthographic: u
// = x, b = P30).
void ndcTerms(const glm::mat4& P, glm::vec2& a, glm::vec2& b) {
  a = glm::vec2(P[0][0], P[1][1]);
  b = P[2][3] != 0.0f ? glm::vec2(-P[2][0], -P[2][1]) : glm::vec2(P[3][0], P[3][1]);
}

// `base` with its texel grid rotated by `angle` about the window centre and scaled by `scale` (>= 1, so the rotated
// window still holds the fitted one), then shifted by `offset` texels. The rotation turns the light's eye about its
// axis and re-centres the window (ndc' = (a / s) R (u - c) in the light's x/y units u), so the projection keeps the
// rasterizer's separable form; the shift moves clip x, y by offset * 2 / size times w.
LightView jitteredView(const LightView& base, float angle, float scale, glm::vec2 offset) {
  LightView v = base;
  glm::mat4& P = v.raster.projection;
  const bool perspective = P[2][3] != 0.0f;
  if (angle != 0.0f || scale != 1.0f) {
    glm::vec2 a, b;
    ndcTerms(P, a, b);
    const glm::vec2 centre = -b / a;
    const float c = std::cos(angle), s = std::sin(angle);
    const glm::vec2 rotated(c * centre.x - s * centre.y, s * centre.x + c * centre.y);
    const glm::vec2 a2 = a / scale, b2 = -a2 * rotated;
    P[0][0] = a2.x, P[1][1] = a2.y;
    if (perspective)
      P[2][0] = -b2.x, P[2][1] = -b2.y;
    else
      P[3][0] = b2.x, P[3][1] = b2.y;
    v.raster.view = glm::rotate(glm::mat4(1.0f), angle, glm::vec3(0, 0, 1)) * base.raster.view;
    v.gpu.texelScale *= scale;
    v.gpu.frustumWidth *= scale;
  }
  const glm::vec2 shift = 2.0f * offset / glm::vec2(v.raster.width, v.raster.height);
  for (int row = 0; row < 2; ++row)
    if (shift[row] != 0.0f)
      for (int col = 0; col < 4; ++col) P[col][row] += shift[row] * P[col][3];
  setLightViewRows(v.gpu.view, v.raster.view);
  setLightViewRows(v.gpu.projection, P);
  return v;
}

// The texel transform from pass 0's map to `to`, whose light eye is pass 0's turned by `angle` about the axis:
// ndc_to = s R (ndc_0 - b_0) + b_to with s = a_to / a_0, so uv_to = c + s R (uv_0 - c) + c (b_to - s R b_0), c the
// map centre. Returned as (s cos, s sin, shift x, shift y), what kernels/jittered.cl's jittered_pass takes.
cl_float4 texelTransform(const LightView& first, const LightView& to, float angle) {
  glm::vec2 a0, b0, a1, b1;
  ndcTerms(first.raster.projection, a0, b0);
  ndcTerms(to.raster.projection, a1, b1);
  const float s = a1.x / a0.x, c = std::cos(angle), sn = std::sin(angle);
  const glm::vec2 rotated(c * b0.x - sn * b0.y, sn * b0.x + c * b0.y);
  const glm::vec2 shift = 0.5f * glm::vec2(to.raster.width, to.raster.height) * (b1 - s * rotated);
  return {{s * c, s * sn, shift.x, shift.y}};
}

struct JitterSettings {
  MapSettings map;
  int receiverPlane = 1;
  int idMode = ID_BUFFER_OFF;
  bool exactEdges = false;
  int confidence = JITTER_OPTIMAL;  // JITTER_* mode
  float confidenceThreshold = 0;
  int agreement = 0;  // jitter-agreement
  float precision = 0;
  int passes = 0, window = 0;
  double epsilon = 0;
  bool scissor = true;
  float rotation = 0, reduction = 0;  // jitter-rotation (degrees), jitter-reduction
  float nJitter = 0;                  // lispsm-n-jitter
  // Throws std::invalid_argument for rotation or reduction with --warp lispsm, and n jitter without it.
  static JitterSettings from(const Params& params, int mapSize) {
    JitterSettings s;
    s.map = MapSettings::from(params, mapSize);
    s.receiverPlane = params.getInt("receiver-plane");
    s.idMode = params.getInt("id-buffer");
    s.exactEdges = params.getInt("exact-edges") != 0;
    s.confidence = params.getInt("confidence");
    s.confidenceThreshold = static_cast<float>(params.get("confidence-threshold"));
    s.agreement = params.getInt("jitter-agreement");
    s.precision = static_cast<float>(params.get("jitter-precision"));
    s.passes = params.getInt("jitter-passes");
    s.window = params.getInt("jitter-window");
    s.epsilon = params.get("jitter-epsilon");
    s.scissor = params.getInt("jitter-scissor") == 1;
    s.rotation = static_cast<float>(params.get("jitter-rotation"));
    s.reduction = static_cast<float>(params.get("jitter-reduction"));
    s.nJitter = static_cast<float>(params.get("lispsm-n-jitter"));
    // LiSPSM (--warp lispsm): translational jitter only; a rotated or reduced warped map is no similarity of the
    // first.
    if (s.map.fit.warp.lispsm && (s.rotation != 0.0f || s.reduction != 0.0f))
      throw std::invalid_argument(
          "--jitter-rotation and --jitter-reduction need --warp none (jittered warps its map with lispsm by default)");
    if (s.nJitter > 0.0f && !s.map.fit.warp.lispsm) throw std::invalid_argument("--lispsm-n-jitter needs --warp lispsm");
    return s;
  }
  bool operator==(const JitterSettings&) const = default;
};

class Jittered final : public TechniqueOf<JitterSettings> {
 public:
  using TechniqueOf::TechniqueOf;

  void render(ShadowFrame& frame, Buffer<float>& visibility) override {
    const Plan plan = planPasses(frame);
    rayRadius_ = settings_.exactEdges ? frame.scene.boundingRadius() : 0.0f;  // read by pass 0's exact edges only
    reset(frame.ctx, static_cast<size_t>(frame.gbuffer.width) * frame.gbuffer.height);
    const int mode = settings_.confidence, maxPasses = settings_.passes;
    const int window = settings_.window;
    const double epsilon = settings_.epsilon;
    int quiet = 0;
    int64_t covered = 0;  // pass 0's receivers: the stopping rule's denominator (later passes see their list only)
    std::optional<Scissor> scissor;
    // Optimal without rotation or reduction: each pass marks the map tiles its unconfident pixels will read, and
    // the next pass draws only those (inside the scissor box of the same lookups).
    // Rotated, reduced or n-jittered passes move distant texels by more than the margin: they draw whole maps.
    masking_ = settings_.scissor && mode == JITTER_OPTIMAL && plan.maxAngle == 0.0f &&
               plan.reduction == 0.0f && plan.nJitter == 0.0f;
    LightView first;  // pass 0's view: every later pass's lookups are moved from its texels
    for (int pass = 0; pass < maxPasses; ++pass) {
      const float angle = plan.maxAngle * 2.0f * centred(static_cast<uint32_t>(pass), 5);
      const glm::vec2 offset(centred(pass, 2), centred(pass, 3));
      if (pass > 0 || plan.scale != 1.0f) {
        map_.view = jitteredView(
            pass > 0 && plan.nJitter > 0.0f ? nJitteredView(frame, plan, pass) : baseView(frame, plan, pass), angle,
            plan.scale, offset);
        map_.view.raster.scissor = scissor;
        map_.view.raster.writeTriangleIds = map_.triangleIds && (pass == 0 || settings_.idMode != ID_BUFFER_OFF);
        if (masking_) map_.view.raster.tileMask = &tileMask_;
        map_.view.raster.casterLight = rasterLightOf(frame.light);  // as pass 0's (renderShadowMap, castersOnly)
        frame.raster.draw(map_.view.raster, map_.targets);
      }
      if (pass == 0) {  // renderShadowMap uploaded the unscaled view; a rotation's common scale redrew it
        if (plan.scale != 1.0f) map_.gpu.upload(frame.ctx, std::span<const LightViewGpu>(&map_.view.gpu, 1));
        first = map_.view;
      }
      // A shift in NDC is a shift in texels for any projection, warped ones included.
      const cl_float4 jitter =
          plan.warped ? cl_float4{{1.0f, 0.0f, offset.x, offset.y}} : texelTransform(first, map_.view, angle);
      const std::array<int32_t, JITTER_COUNTERS> count = pass > 0 && plan.nJitter > 0.0f
                                                             ? reproject(frame, pass, visibility)
                                                             : accumulate(frame, pass, jitter, visibility);
      passes_ = pass + 1;
      if (pass == 0) covered = count[0];
      active_ = count[JITTER_ACTIVE];
      std::swap(work_, next_);
      const double limit = epsilon * static_cast<double>(covered);
      if (active_ == 0) break;                                 // every pixel is final
      if (mode == JITTER_OPTIMAL && count[2] <= limit) break;  // every pixel (but epsilon) has what it needs
      quiet = pass > 0 && count[1] <= limit ? quiet + 1 : 0;
      if (quiet >= window) break;
      if (masking_) scissor = nextScissor(count, plan.fitted.raster.width);
    }
    frame.attributes["penumbra:jitter-passes"] = fmt::format("{} of at most {}", passes_, maxPasses);
  }

  void addDebugChannels(Context& ctx, Image& image) override {
    const std::vector<JitterPixel> state = state_.download(ctx);
    std::vector<float> pass(state.size()), kept(state.size()), settled(state.size()), required(state.size());
    for (size_t i = 0; i < state.size(); ++i) {
      pass[i] = state[i].pass;
      settled[i] = state[i].kept == JITTER_SETTLED ? 1.0f : 0.0f;
      kept[i] = std::clamp(state[i].kept, 0.0f, 1.0f);
      required[i] = 1.0f - state[i].slack;  // optConf, eq. 5
    }
    image.add("pass.Y", pass);
    image.add("confidence.Y", kept);
    if (settings_.confidence == JITTER_OPTIMAL && settings_.agreement > 0) image.add("settled.Y", settled);
    if (settings_.confidence == JITTER_OPTIMAL) image.add("requiredConfidence.Y", required);
  }

 private:
  // What every pass of a frame shares: the fitted map of pass 0 (sm's), the rotation's range and its texel scale,
  // the frustum reduction's factor and the camera's depth range it cuts.
  struct Plan {
    LightView fitted;
    float maxAngle = 0, scale = 1, reduction = 0, margin = 1;
    ViewDepthRange depth;
    bool warped = false;
    float nJitter = 0, n0 = 0;  // LiSPSM n jitter (log2 range) and pass 0's warp distance
  };

  Plan planPasses(ShadowFrame& frame) {
    Plan plan;
    plan.maxAngle = glm::radians(settings_.rotation);
    // Every pass shares one texel size, so confidences of different passes compare (sec. 6.5.1's caveat).
    plan.scale = std::cos(plan.maxAngle) + std::sin(plan.maxAngle);
    plan.reduction = settings_.reduction;
    plan.warped = settings_.map.fit.warp.lispsm;
    plan.nJitter = settings_.nJitter;
    map_.triangleIds = settings_.idMode != ID_BUFFER_OFF || settings_.exactEdges;  // exact edges: pass 0's ids
    map_.castersOnly = true;  // depth comparisons only: the maps leave out what can shadow no receiver
    renderShadowMap(frame, settings_.map, map_, 0.0f);
    plan.fitted = map_.view;
    if (plan.reduction > 0.0f || plan.nJitter > 0.0f) plan.depth = tightViewDepth(frame.ctx, frame.gbuffer);
    plan.margin = settings_.map.normalOffset + 1.0f;  // renderShadowMap's, no filter reach
    if (plan.nJitter > 0.0f) {  // pass 0's n, as renderShadowMap's fit chose it
      LispsmFit fit;
      fitWarpedLightView(frame, settings_.map.fit.warp, settings_.map.size, plan.margin, plan.depth.near,
                         plan.depth.far, receivers(frame), &fit);
      if (fit.warped)
        plan.n0 = fit.n;
      else
        plan.nJitter = 0.0f;  // an empty or degenerate body: the map is uniform, there is no n to vary
    }
    passes_ = 0;
    return plan;
  }

  const ReceiverBounds* receivers(ShadowFrame& frame) const {
    return settings_.map.fit.fitReceivers ? &frame.receivers : nullptr;
  }

  // Pass k's map under LiSPSM n-parameter jittering (Luksch sec. 6.5.1): pass 0's warp with n scaled by
  // 2^(J h_k), h_k in [-1, 1) from the Halton sequence in base 7 (bases 2 and 3 shift it, base 5 rotates), so
  // passes alternate between more texels near the camera (smaller n) and more far away (larger n).
  LightView nJitteredView(ShadowFrame& frame, const Plan& plan, int pass) const {
    WarpSettings warp = settings_.map.fit.warp;
    warp.n = plan.n0 * std::exp2(plan.nJitter * 2.0f * centred(static_cast<uint32_t>(pass), 7));
    return fitWarpedLightView(frame, warp, settings_.map.size, plan.margin, plan.depth.near, plan.depth.far,
                              receivers(frame), nullptr);
  }

  // Pass k's map before its jitter: pass 0's, or with frustum reduction (sec. 6.5.2) the camera's frustum
  // [near, far factor^k] cropped like a pssm split.
  LightView baseView(const ShadowFrame& frame, const Plan& plan, int pass) const {
    if (plan.reduction == 0.0f || pass == 0) return plan.fitted;
    const float far =
        std::max(plan.depth.far * std::pow(plan.reduction, static_cast<float>(pass)), plan.depth.near * 1.01f);
    return sliceLightView(frame, settings_.map, plan.depth.near, far, plan.margin);
  }

  // The per-pixel buffers, reused across frames (pass 0 writes every pixel's state and visibility).
  void reset(Context& ctx, size_t pixels) {
    state_.allocate(ctx, pixels);
    work_.allocate(ctx, pixels);
    next_.allocate(ctx, pixels);
    counters_.allocate(ctx, JITTER_COUNTERS);
  }

  // With masking_, the next pass draws only the texels the still-unconfident pixels look up, their box widened by
  // JITTER_DRAW_MARGIN texels (and within it, through the tile mask, only the tiles near those lookups). Final pixels
  // are never looked up again, so the texels outside keep an older pass's content unread.
  static std::optional<Scissor> nextScissor(const std::array<int32_t, JITTER_COUNTERS>& count, int size) {
    if (count[2] == 0) return std::nullopt;
    constexpr int kMargin = JITTER_DRAW_MARGIN;
    const int* box = &count[JITTER_BOX_MIN_X];
    return Scissor{std::clamp(box[0] - kMargin, 0, size), std::clamp(box[1] - kMargin, 0, size),
                   std::clamp(box[2] + 1 + kMargin, 0, size), std::clamp(box[3] + 1 + kMargin, 0, size)};
  }

  // A pass of n jitter: every listed pixel projected through this pass's own warped map (jittered_reproject).
  std::array<int32_t, JITTER_COUNTERS> reproject(ShadowFrame& frame, int pass, Buffer<float>& visibility) {
    const GBuffer& g = frame.gbuffer;
    const JitterShade shade = shadeArgs(frame, 0);
    const ShadeFrame frameShade = shadeFrame(frame, settings_.map, settings_.receiverPlane, settings_.idMode);
    JitterPass jp{};
    jp.pass = pass, jp.count = static_cast<uint32_t>(active_), jp.idMode = frameShade.idMode;
    resetCounters(frame.ctx);
    passGpu_.allocate(frame.ctx, 1);
    passGpu_.upload(frame.ctx, std::span<const LightViewGpu>(&map_.view.gpu, 1));
    Kernel kernel(frame.ctx, "kernels/jittered.cl", "jittered_reproject", "shade");
    kernel
        .args(g.position, g.normal, work_, map_.targets.depth, passGpu_, frameShade, map_.targets.triangleId,
              frame.raster.objectIds(), g.triangleId, g.objectId, shade, jp, state_, counters_, next_, visibility)
        // per listed pixel: its index, its position and normal, four neighbours' positions (eq. 5), its state read
        // and written, and the next list's entry
        .moves(uint64_t(active_) * (4 + 16 * 6 + 2 * sizeof(JitterPixel) + 4))
        .launch(static_cast<size_t>(active_), size_t{JITTER_GROUP});
    return readCounters(frame.ctx);
  }

  // The technique's scalars (kernels/shared/jittered.h), with a tile mask of maskTiles^2 tiles (0: none).
  JitterShade shadeArgs(const ShadowFrame& frame, int maskTiles) const {
    return {settings_.confidence,
            settings_.confidenceThreshold,
            settings_.agreement,
            settings_.precision,
            maskTiles,
            maskTiles,
            kRasterTileSize,
            settings_.exactEdges ? 1 : 0,
            frame.raster.deviceScene().materials.alphaTested ? 1u : 0u,
            rayRadius_,
            frame.raster.deviceScene().triangleCount};
  }

  void resetCounters(Context& ctx) {
    constexpr int32_t kLow = std::numeric_limits<int32_t>::min(), kHigh = std::numeric_limits<int32_t>::max();
    const std::array<int32_t, JITTER_COUNTERS> reset = {0, 0, 0, 0, kHigh, kHigh, kLow, kLow};
    counters_.upload(ctx, std::span<const int32_t>(reset));
  }

  std::array<int32_t, JITTER_COUNTERS> readCounters(Context& ctx) {
    const std::vector<int32_t> c = counters_.download(ctx);
    std::array<int32_t, JITTER_COUNTERS> result;
    std::copy(c.begin(), c.end(), result.begin());
    return result;
  }

  // One pass: pass 0 tests every receiver through the map as sm does and records its lookup; later passes move
  // that lookup by `jitter`, their texel transform from pass 0 (kernels/jittered.cl). Returns the pass's counters.
  std::array<int32_t, JITTER_COUNTERS> accumulate(ShadowFrame& frame, int pass, cl_float4 jitter,
                                                  Buffer<float>& visibility) {
    const GBuffer& g = frame.gbuffer;
    const uint32_t width = static_cast<uint32_t>(g.width), height = static_cast<uint32_t>(g.height);
    const uint64_t pixels = uint64_t{width} * height;
    const int idMode = settings_.idMode;
    resetCounters(frame.ctx);
    const int size = map_.view.raster.width, tiles = (size + kRasterTileSize - 1) / kRasterTileSize;
    tileMask_.allocate(frame.ctx, masking_ ? static_cast<size_t>(tiles) * tiles : 1);
    if (masking_) tileMask_.fill(frame.ctx, 0u);  // the previous pass's draw has read it
    const int maskTiles = masking_ ? tiles : 0;   // 0: the kernels mark nothing
    const JitterShade shade = shadeArgs(frame, maskTiles);
    if (pass == 0) {
      const ShadeFrame frameShade = shadeFrame(frame, settings_.map, settings_.receiverPlane, idMode);
      Kernel kernel(frame.ctx, "kernels/jittered.cl", "jittered_first", "shade");
      const raster::SceneBuffers& scene = frame.raster.deviceScene();
      kernel
          .args(g.position, g.normal, map_.targets.depth, map_.gpu, frameShade, map_.targets.triangleId,
                frame.raster.objectIds(), g.triangleId, g.objectId, shade, scene.positions, scene.triangles,
                scene.alphaIndex, scene.alphaTriangles, scene.alphaMaterials, scene.alphaTexels, state_, counters_,
                next_, tileMask_, visibility)
          // + the state; the work list's entries as a bound
          .moves(pixels * (kVisibilityBytesPerPixel + sizeof(JitterPixel) + 4))
          .launch(pixels, size_t{JITTER_GROUP});
    } else {
      const JitterPass jp{jitter, size, size, map_.view.gpu.zFar, pass, static_cast<uint32_t>(active_), idMode, {0, 0}};
      Kernel kernel(frame.ctx, "kernels/jittered.cl", "jittered_pass", "shade");
      kernel
          .args(work_, map_.targets.depth, map_.targets.triangleId, frame.raster.objectIds(), g.triangleId, g.objectId,
                shade, jp, state_, counters_, next_, tileMask_, visibility)
          // per listed pixel: its index, its state read and written, and the next list's entry
          .moves(uint64_t(active_) * (4 + 2 * sizeof(JitterPixel) + 4))
          .launch(static_cast<size_t>(active_), size_t{JITTER_GROUP});
    }
    return readCounters(frame.ctx);
  }

  ShadowMap map_;
  Buffer<JitterPixel> state_;  // per pixel: pass 0's lookup, slack, what is kept (kernels/shared/jittered.h)
  Buffer<int32_t> counters_;
  Buffer<uint32_t> work_, next_;  // the pixels the next pass tests, and the list it writes for the one after
  int32_t active_ = 0;            // work_'s length
  Buffer<uint32_t> tileMask_;     // map tiles the next pass draws (RasterView::tileMask), when masking_
  Buffer<LightViewGpu> passGpu_;  // an n-jittered pass's own light view (jittered_reproject)
  bool masking_ = false;          // this frame's later passes draw only what their listed pixels read
  int passes_ = 0;
  float rayRadius_ = 0.0f;  // the scene's bounding radius, the exact edges' ray offset floor (this frame's)
};

}  // namespace

TechniqueInfo jitteredTechnique() {
  std::vector<ParamSpec> params = shadowMapParams();
  unscaledNormalOffset(params);
  fixMapSize(params, "the jittered passes' map, whose confidence accumulation needs a fixed texel grid");
  // A quarter of sm's normal offset by default: the offset moves a receiver's lookup sideways wherever the light is
  // not along the normal (tan(angle) texels: a spot light's shadow edges shrink by that much), a misplacement no
  // number of passes can undo, while the receiver-plane comparison at the texel centre already keeps planar
  // receivers free of acne (Luksch sec. 9: with confident samples only, bias is "no real problem"); grazing
  // receivers under a step's edge still need a little of it. Measured in the README.
  paramNamed(params, "normal-offset").defaultValue = 0.25;
  params.push_back(receiverPlaneParam());
  params.push_back(idBufferParam());
  params.push_back(exactEdgesParam());
  // LiSPSM by default: jittering removes projection aliasing, the warp perspective aliasing (Luksch sec. 5-6 combine
  // them); measured in the README's comparison (every case as accurate or more, at about the same time).
  for (ParamSpec& spec : warpParams(true)) params.push_back(spec);
  params.push_back({"confidence",
                    JITTER_OPTIMAL,
                    JITTER_SIMPLE,
                    JITTER_OPTIMAL,
                    "Accumulation (Luksch sec. 6.2-6.3): simple (confident lookups add shadow), adapted (the most "
                    "confident lookup wins), optimal (adapted, final once a pixel has the confidence it needs)",
                    {"simple", "adapted", "optimal"}});
  params.push_back({"confidence-threshold", 0.5, 0, 1, "simple: the confidence (eq. 4) a lookup needs to add shadow"});
  params.push_back({"jitter-precision", 0.125, 0, 1,
                    "optimal: the required confidence of eq. 5 scaled: a lookup is final within precision / 2 pixel "
                    "spacings of its texel centre (1: the paper; smaller: closer to the ray-traced pixel centre)"});
  params.push_back({"jitter-agreement", 2, 0, 64,
                    "optimal without the ID buffer: a pixel is also final once this many consecutive passes found "
                    "the 3x3 texels around its lookup all giving its kept result (beyond the paper; 0: off)"});
  params.push_back({"jitter-passes", 32, 1, 256, "Most passes (jittered maps) per frame"});
  params.push_back({"jitter-epsilon", 5e-5, 0, 1,
                    "Stop when the last jitter-window passes each changed at most this fraction of the covered "
                    "pixels (optimal: or at most this fraction still lacks the confidence it needs)"});
  params.push_back({"jitter-window", 4, 1, 64, "Consecutive quiet passes the stopping rule waits for"});
  params.push_back({"jitter-scissor",
                    1,
                    0,
                    1,
                    "optimal without rotation: draw later passes only over the texels still-unconfident pixels read",
                    {"off", "on"}});
  params.push_back({"jitter-reduction", 0, 0, 0.95,
                    "Frustum reduction (Luksch sec. 6.5.2): pass k's map covers the camera's depths up to far * "
                    "factor^k only (its texels finer; required confidence scaled, eq. 7); 0 = off"});
  params.push_back({"lispsm-n-jitter", 0, 0, 1,
                    "LiSPSM n-parameter jittering (Luksch sec. 6.5.1, --warp lispsm): later passes scale n by up to "
                    "2^J either way, each pass projected again with its own required confidence; 0 = off"});
  params.push_back({"jitter-rotation", 0, 0, 45,
                    "Largest rotational jitter about the light axis, degrees (Halton base 5); the map's texels grow "
                    "by cos + sin of it so every rotated pass still covers the fitted window"});
  return {"jittered",
          "Confidence-based jittered shadow maps: Halton-jittered passes of sm's map accumulated by confidence "
          "(simple/adapted/optimal) with a device-counted stopping rule",
          params,
          makeTechnique<Jittered>,
          /*pointLightRefusal=*/{},
          "it accumulates passes of maps drawn with sub-texel jitter until each pixel's confidence suffices (Luksch "
          "sec. 5): each pass is a draw of the scene, not one map"};
}

}  // namespace penumbra
