// A shadow technique: composes stages (shadow map, filtering, ...) and a visibility kernel. Each technique
// lives in its own files (host/techniques/NAME.cpp + kernels/NAME.cl) and one line of the registry.
#pragma once

#include <functional>
#include <map>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "host/cl/buffer.h"
#include "host/cl/context.h"
#include "host/io/image.h"
#include "host/scene/scene.h"
#include "host/scene/solids.h"
#include "host/techniques/params.h"
#include "host/views/light_fit.h"
#include "host/views/views.h"
#include "raster/rasterizer.h"

namespace penumbra {

// A light's depth map drawn by the caller (pn_shade, host/pipeline/caller_shade.h): renderShadowMap takes its view and
// its texels instead of fitting and rasterizing the scene.
struct CallerMap {
  LightView view;  // the caller's matrices as a map's view (view.raster is not drawn)
  // Writes the map, view.gpu.width^2 linear light depths (+INFINITY where empty, rows from the bottom), into `depth`.
  std::function<void(Buffer<float>& depth)> writeDepth;
};

// What a technique gets for one frame: the device, the rasterizer holding the scene, the light, the
// camera's G-buffer (world positions and normals per pixel) and the light-space box of the receivers it
// sees (what the light's map is fitted to).
struct ShadowFrame {
  Context& ctx;
  Rasterizer& raster;
  const Scene& scene;
  const Light& light;
  const Camera& camera;
  const GBuffer& gbuffer;
  const ReceiverBounds& receivers;
  // Provenance the technique records for the output's header ("penumbra:light-fit", ...).
  std::map<std::string, std::string> attributes = {};
  // A cube face's point light (host/pipeline/point_light.h; `light` is then the face's square spot light), else null:
  // for techniques that sample the light's own shape (izb's sphere).
  const Light* pointLight = nullptr;
  // The caller's map (pn_shade), else null: the scene is then a stand-in of no triangles whose bounds are the caller's
  // scene's, and the rasterizer holds nothing.
  const CallerMap* callerMap = nullptr;
  // The scene's solids (host/scene/solids.h), found once by the renderer; null: a technique that needs them finds them.
  const Solids* solids = nullptr;
  // Under --map-size auto, the size the camera's pixels alone need (before the penumbrae cap it; rounded and clamped as
  // the map size), which split techniques plan their split count with (host/techniques/split_maps.h); 0: none.
  int pixelsMapSize = 0;
};

class Technique {
 public:
  virtual ~Technique() = default;
  // Writes per-pixel visibility (fraction of the light reaching the point, 0..1; 1 for background) into
  // `visibility`, which holds gbuffer.width * gbuffer.height elements. Never NaN.
  virtual void render(ShadowFrame& frame, Buffer<float>& visibility) = 0;
  // Debug channels ("blocker.Z", "moments.R", ...) from the last render, rows bottom-up like the G-buffer.
  virtual void addDebugChannels(Context& /*ctx*/, Image& /*image*/) {}
  // Whether `params` (with `mapSize`, the frame's choice under --map-size auto) parse into this instance's settings:
  // an instance is its typed settings, so the renderer keeps it for as long as this holds.
  virtual bool matches(const Params& params, int mapSize) const = 0;
};

// A technique whose instance holds `Settings`, its parameters parsed once: `Settings::from(params, mapSize)` reads
// every value it needs (and throws std::invalid_argument naming the options when they contradict each other),
// `operator==` compares two instances' settings.
template <class S>
class TechniqueOf : public Technique {
 public:
  using Settings = S;
  explicit TechniqueOf(Settings settings) : settings_(std::move(settings)) {}
  bool matches(const Params& params, int mapSize) const override {
    return Settings::from(params, mapSize) == settings_;
  }

 protected:
  const Settings settings_;
};

// TechniqueInfo::create for a TechniqueOf subclass `T` made from its settings alone.
template <class T>
std::unique_ptr<Technique> makeTechnique(const Params& params, int mapSize) {
  return std::make_unique<T>(T::Settings::from(params, mapSize));
}

struct TechniqueInfo {
  std::string name;  // --technique NAME
  std::string description;
  std::vector<ParamSpec> params;
  // An instance from `params` parsed into the technique's settings; `mapSize` is the frame's choice under --map-size
  // auto (host/pipeline/map_size.h) and is ignored otherwise. Throws std::invalid_argument for contradicting values.
  std::function<std::unique_ptr<Technique>(const Params& params, int mapSize)> create;
  // Point lights: empty when the technique shadows them, as six cube faces that it renders as spot lights
  // (host/pipeline/point_light.h); otherwise why six spot faces cannot work for it (the refusal's reason).
  std::string pointLightRefusal = {};
  // Empty when the technique shades from one light depth map the caller drew (pn_shade: ShadowFrame::callerMap);
  // otherwise why it cannot (it draws maps of its own choosing, or none).
  std::string callerMapRefusal = {};
  // Where its per-pixel kernels (a blocker search, a penumbra filter) are clamped: the half-width in texels of a map of
  // mapSize texels a side; empty when they are not. --map-size auto keeps the median penumbra within it
  // (host/pipeline/map_size.h).
  std::function<double(const Params& params, int mapSize)> kernelReach = {};

  bool hasParam(const std::string& param) const;  // a parameter of that name (without dashes)
  bool shadowsPointLights() const { return pointLightRefusal.empty(); }
};

// The registry, in the order `penumbra render --help` lists them.
const std::vector<TechniqueInfo>& techniques();
// Throws std::invalid_argument listing the known names.
const TechniqueInfo& findTechnique(const std::string& name);

// Parameter values as text by name (no dashes), as the command line and scene files give them.
using ParamValues = std::map<std::string, std::string>;

// The technique's defaults with `values` applied. strict: a value the technique has no parameter for throws
// std::invalid_argument ("--NAME does not apply to technique 'T'"); else it is skipped. Bad values always throw
// (Params::set).
Params techniqueParams(const TechniqueInfo& info, const ParamValues& values, bool strict = true);

// Throws std::invalid_argument (a usage error: call it before any work) when `light` is a point light that
// `technique` cannot shadow: "light L is a point light, which technique T cannot shadow (REASON); point lights work
// with sm, pcf, ...".
void refuseUnsupportedLight(const Light& light, const TechniqueInfo& technique);

}  // namespace penumbra
