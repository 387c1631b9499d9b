// Shadow-map rendering shared by sm, pcf, pcss and the moment-based techniques.
#include "host/techniques/shadow_map.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <stdexcept>
#include <string>

#include "host/techniques/warp.h"
#include "host/views/light_fit.h"
#include "kernels/shared/id_buffer.h"

namespace penumbra {

namespace {
// The size of the techniques without auto.
constexpr int kMapSizeFixed = 2048;
// --map-size auto: the smallest size, and the texels across a penumbra's half-width and a thin caster's width
// (calibrated on docs/default-front.md's sweeps).
// A filter traces a penumbra's ramp when its half-width spans 6 texels; a hard edge (sm) or a short kernel (pcf) is
// placed within a third of the half-width with 3, and more texels buy it nothing: the penumbra it cannot draw is the
// larger error.
constexpr int kMapSizeMin = 256;
constexpr double kPenumbraTexels = 6.0;
constexpr double kShortPenumbraTexels = 3.0;
// Beyond a median half-width of 16 texels (the moment blur's widest) a filter's taps only spread thinner; sm and pcf
// (a 4-texel kernel) gain nothing beyond 4.
constexpr double kPenumbraMaxTexels = 16.0;
constexpr double kShortPenumbraMaxTexels = 4.0;
constexpr double kDetailTexels = 2.0;
constexpr double kPenumbraQuantile = 0.1;
constexpr double kBlurredPenumbraQuantile = 0.2;
}  // namespace

std::vector<ParamSpec> shadowMapParams() {
  ParamSpec mapSize{"map-size", 0, 16, 8192,
                    "Shadow-map width and height in texels, or auto: the largest of what the camera's pixels need "
                    "(--map-size-quantile of them get a texel per pixel; capped by --map-size-penumbra-max), what the "
                    "penumbrae need (--map-size-penumbra) and what thin casters need (--map-size-detail), rounded up "
                    "to a multiple of 128 within --map-size-min..--map-size-max"};
  mapSize.autoName = "auto";  // autoValue 0: the default
  return {
      mapSize,
      {"map-size-quantile", 0.9, 0.01, 1, "--map-size auto: the share of the camera's pixels that get a texel each"},
      {"map-size-penumbra", kPenumbraTexels, 0, 64,
       "--map-size auto, area lights: the penumbra half-width that --map-size-penumbra-quantile of the shadowed pixels "
       "reach spans at least this many texels (measured on a 512^2 probe of the light's view; 0: off)"},
      {"map-size-penumbra-quantile", kPenumbraQuantile, 0.01, 1,
       "--map-size auto: the share of the shadowed pixels whose penumbra may be narrower than --map-size-penumbra"},
      {"map-size-penumbra-max", kPenumbraMaxTexels, 0, 256,
       "--map-size auto, area lights: the pixels' need is capped where the median penumbra half-width would span more "
       "texels than this (wider penumbrae are filtered: more texels buy nothing; 0: off)"},
      {"map-size-detail", kDetailTexels, 0, 64,
       "--map-size auto: the thinnest 5 % of the casters' features (legs, poles, bars between alpha holes, measured "
       "on the probe) span at least this many texels (0: off)"},
      {"map-size-min", kMapSizeMin, 16, 8192, "--map-size auto: the smallest size"},
      {"map-size-max", 4096, 16, 8192, "--map-size auto: the largest size"},
      {"fit", 1, 0, 1, "Light frustum fitted to the whole scene, or to the receivers the camera sees",
       {"scene", "receivers"}},
      {"bias", 1.0, 0, 100, "Constant depth bias, in texel footprints at the receiver"},
      {"slope-bias", 1.0, 0, 100,
       "Slope-scaled depth bias, in texel footprints times the receiver's depth slope in the map (a sun's: tan(angle "
       "to the light))"},
      {"normal-offset", 1.0, 0, 100,
       "Receiver offset along its normal, in texel footprints, times sin(angle to the light)"},
      {"cube-guard", 32, 0, 2048,
       "Point lights: each cube face's map reaches this many texels beyond its 90-degree square on every side, so "
       "filters near a face edge read drawn texels (at most map-size / 4)"},
  };
}

void unscaledNormalOffset(std::vector<ParamSpec>& params) {
  paramNamed(params, "normal-offset").help = "Receiver offset along its normal, in texel footprints, at every angle";
}

void shortPenumbraMapSize(std::vector<ParamSpec>& params) {
  paramNamed(params, "map-size-penumbra").defaultValue = kShortPenumbraTexels;
  paramNamed(params, "map-size-penumbra-max").defaultValue = kShortPenumbraMaxTexels;
}

void blurredPenumbraMapSize(std::vector<ParamSpec>& params) {
  paramNamed(params, "map-size-penumbra-quantile").defaultValue = kBlurredPenumbraQuantile;
}

void splitMapSize(std::vector<ParamSpec>& params) {
  ParamSpec& size = paramNamed(params, "map-size");
  size.help = fmt::format(
      "Each split's map width and height in texels, or auto: the size one map of the whole view would need "
      "(--map-size auto's needs, measured on the light's whole view; a split, cropped to its slice, has at least "
      "that map's texel density), at most --map-size-max ({} here); --pssm-splits auto adapts the split count to it",
      kMapSizeFixed);
  paramNamed(params, "map-size-max").defaultValue = kMapSizeFixed;
}

void fixMapSize(std::vector<ParamSpec>& params, const std::string& why) {
  std::erase_if(params, [](const ParamSpec& spec) { return spec.name.starts_with("map-size-"); });
  for (ParamSpec& spec : params)
    if (spec.name == "map-size") {
      spec.autoName.clear();
      spec.defaultValue = kMapSizeFixed;
      spec.help = fmt::format("Shadow-map width and height in texels (no auto: {})", why);
    }
}

namespace {
constexpr double kAutoRadius = -1.0;  // a radius parameter's auto value (outside [0, max])
}  // namespace

std::vector<ParamSpec> autoRadiusParams(const std::string& name, const std::string& help, double max, double maxDefault,
                                        const std::string& maxNote) {
  ParamSpec radius{name, kAutoRadius, 0, max,
                   fmt::format("{}; auto: matched to the penumbra half-width h that --{}-quantile of the shadowed "
                               "pixels reach, r = floor(h) up to --{}-max",
                               help, name, name)};
  radius.autoName = "auto";
  radius.autoValue = kAutoRadius;
  return {radius,
          {name + "-quantile", 0.05, 0.01, 1,
           fmt::format("--{} auto: the share of the camera's shadowed pixels whose penumbra the kernel matches or "
                       "exceeds",
                       name)},
          {name + "-max", maxDefault, 0, max, fmt::format("--{} auto: the largest radius{}", name, maxNote)}};
}

std::vector<ParamSpec> pcfRadiusParams() {
  // Auto by default, at most 4 (81 taps): docs/techniques/sm-pcf-pcss.md ("The kernel from the scene's penumbrae").
  return autoRadiusParams("pcf-radius", "PCF kernel half-width r in texels; the grid has (2r+1)^2 bilinear taps", 16,
                          4);
}

ParamSpec AutoReach::param(const std::string& name, int min, int max, const std::string& help) const {
  const int tens = divisor % 100 / 10, units = divisor % 10;
  const char* ordinal = tens == 1 || units == 0 || units > 3 ? "th" : units == 1 ? "st" : units == 2 ? "nd" : "rd";
  ParamSpec spec{name, min - 1.0, static_cast<double>(min), static_cast<double>(max),
                 fmt::format("{}; auto: a {}{} of the map's side, at least {}", help, divisor, ordinal, minimum)};
  spec.autoName = "auto";
  spec.autoValue = min - 1.0;
  return spec;
}

float AutoReach::texels(const Params& params, const std::string& name, int mapSize) const {
  if (!params.isAuto(name)) return static_cast<float>(params.get(name));
  return static_cast<float>(std::max(mapSize / divisor, minimum));
}

AutoRadius AutoRadius::from(const Params& params, const std::string& name) {
  AutoRadius r;
  r.name = name;
  r.automatic = params.isAuto(name);
  r.radius = r.automatic ? 0 : params.getInt(name);
  r.quantile = params.get(name + "-quantile");
  r.max = params.getInt(name + "-max");
  return r;
}

int chooseFromPenumbra(ShadowFrame& frame, const Buffer<float>& depth, const Buffer<LightViewGpu>& view,
                       const ReceiverBias& bias, double quantile, const std::string& name,
                       const std::function<int(double halfWidth)>& choose) {
  const PenumbraWidth width = measurePenumbraWidth(frame.ctx, frame.gbuffer, depth, view, bias, quantile);
  const int value = choose(width.halfWidth);
  frame.attributes["penumbra:" + name] =
      width.pixels == 0 ? fmt::format("auto {} (no shadowed pixel measured)", value)
                        : fmt::format("auto {} (quantile {} of {} shadowed pixels: penumbra half-width {:.3g} texels)",
                                      value, quantile, width.pixels, width.halfWidth);
  return value;
}

int resolveAutoRadius(ShadowFrame& frame, const Buffer<float>& depth, const Buffer<LightViewGpu>& view,
                      const ReceiverBias& bias, const AutoRadius& wanted) {
  if (!wanted.automatic) return wanted.radius;
  return chooseFromPenumbra(frame, depth, view, bias, wanted.quantile, wanted.name, [&](double halfWidth) {
    return std::min(static_cast<int>(std::floor(halfWidth)), wanted.max);
  });
}

AutoKernel resolveAutoKernel(ShadowFrame& frame, const Buffer<float>& depth, const Buffer<LightViewGpu>& view,
                             const ReceiverBias& bias, const AutoRadius& radius, float maxWidth) {
  if (!radius.automatic) return {radius.radius, static_cast<float>(radius.radius)};
  AutoKernel kernel;
  kernel.radius = chooseFromPenumbra(frame, depth, view, bias, radius.quantile, radius.name, [&](double halfWidth) {
    kernel.width = static_cast<float>(std::min(std::floor(halfWidth), static_cast<double>(maxWidth)));
    return std::min(static_cast<int>(kernel.width), radius.max);
  });
  frame.attributes["penumbra:pcf-width"] =
      fmt::format("{} texels, {} x {} taps", kernel.width, 2 * kernel.radius + 1, 2 * kernel.radius + 1);
  return kernel;
}

ParamSpec receiverPlaneParam() {
  return {"receiver-plane", 1, 0, 1,
          "Receiver-plane depth bias: compare each texel with the receiver's plane (from neighbouring pixels) "
          "instead of the slope-scaled bias; falls back to it where the plane is unknown",
          {"off", "on"}};
}

ParamSpec exactEdgesParam() {
  return {"exact-edges",
          1,
          0,
          1,
          "Exact shadow edges: where the texels nearest a receiver disagree, its shadow ray is tested exactly "
          "against the triangles they hold (the reference's ray), so edges and thin casters are decided per pixel",
          {"off", "on"}};
}

ParamSpec idBufferParam() {
  return {"id-buffer", ID_BUFFER_OFF, ID_BUFFER_OFF, ID_BUFFER_COMBINED,
          "ID buffer: a receiver is lit where one of its four nearest texels holds its own object or triangle id "
          "(no depth bias); combined: ids between objects, the biased depth test within one",
          {"off", "object", "polygon", "combined"}};
}

MapSettings MapSettings::from(const Params& params, int autoSize) {
  MapSettings m;
  if (params.isAuto("map-size")) {
    if (autoSize <= 0) throw std::logic_error("MapSettings: --map-size auto without the frame's size");
    m.size = autoSize;
  } else {
    m.size = params.getInt("map-size");
  }
  m.fit = {WarpSettings::from(params), params.getInt("fit") == 1};
  m.bias = static_cast<float>(params.get("bias"));
  m.slopeBias = static_cast<float>(params.get("slope-bias"));
  m.normalOffset = static_cast<float>(params.get("normal-offset"));
  return m;
}

ShadeFrame shadeFrame(const ShadowFrame& frame, const MapSettings& settings, int receiverPlane, int idMode) {
  return {static_cast<uint32_t>(frame.gbuffer.width), static_cast<uint32_t>(frame.gbuffer.height), settings.bias,
          settings.slopeBias, settings.normalOffset, receiverPlane, idMode};
}

namespace {

// The view as the header reports it ("penumbra:light-fit") and on the device.
void publishView(ShadowFrame& frame, const MapSettings& settings, ShadowMap& map) {
  const LightViewGpu& gpu = map.view.gpu;
  frame.attributes["penumbra:light-fit"] = fmt::format(
      "{} {}x{} texel {:.4g}{} depth {:.6g}..{:.6g}",
      frame.callerMap != nullptr  ? "caller"
      : settings.fit.fitReceivers ? "receivers"
                                  : "scene",
      gpu.width, gpu.height, gpu.texelScale, gpu.kind == LIGHT_KIND_SPOT ? "/depth" : "", gpu.zNear, gpu.zFar);
  if (map.gpu.empty()) map.gpu.allocate(frame.ctx, 1, CL_MEM_READ_ONLY);
  map.gpu.upload(frame.ctx, std::span<const LightViewGpu>(&map.view.gpu, 1));
}

// zNear tightened to the nearest caster drawn where that lies inside the fit's range.
void tightenNear(LightViewGpu& gpu, float drawnMin) {
  if (drawnMin > gpu.zNear && drawnMin < gpu.zFar) gpu.zNear = drawnMin;
}

}  // namespace

void renderShadowMap(ShadowFrame& frame, const MapSettings& settings, ShadowMap& map, float reachTexels, MapNear near) {
  const int size = settings.size;
  if (frame.callerMap != nullptr) {  // the caller's map: its view, its texels; no triangle ids (no ID buffer)
    map.view = frame.callerMap->view;
    if (map.view.gpu.width != size || map.view.gpu.height != size)
      throw std::logic_error(fmt::format("renderShadowMap: the caller's {}x{} map for a technique of {}^2",
                                         map.view.gpu.width, map.view.gpu.height, size));
    map.targets.depth.allocate(frame.ctx, static_cast<size_t>(size) * size);
    map.targets.triangleId.allocate(frame.ctx, 1);  // an argument the kernels read only with an ID buffer
    map.targets.forgetEmptyTiles();                 // written here, not drawn
    frame.callerMap->writeDepth(map.targets.depth);
  } else {
    const float margin = reachTexels + settings.normalOffset + 1.0f;
    map.view = fitWarpedLightView(frame, settings.fit, size, margin);
    map.view.raster.writeTriangleIds = map.triangleIds;
    if (map.castersOnly || map.casterTiles) map.view.raster.casterLight = rasterLightOf(frame.light);
    map.view.raster.recordCasterTiles = map.casterTiles && !map.castersOnly;
    map.view.raster.receiverReach =
        map.view.raster.recordCasterTiles && map.receiverReach ? map.receiverReach(map.view.gpu) : -1;
    map.targets.keepEmptyTiles = true;  // drawn frame after frame, and only drawn (RasterTargets)
    frame.raster.draw(map.view.raster, map.targets);
  }
  if (near == MapNear::Drawn)
    tightenNear(map.view.gpu, reduceDepthRange(frame.ctx, map.targets.depth, static_cast<size_t>(size) * size).min);
  publishView(frame, settings, map);
}

void tightenMapNear(ShadowFrame& frame, const MapSettings& settings, ShadowMap& map, float drawnMin) {
  const float before = map.view.gpu.zNear;
  tightenNear(map.view.gpu, drawnMin);
  if (map.view.gpu.zNear != before) publishView(frame, settings, map);
}

}  // namespace penumbra
