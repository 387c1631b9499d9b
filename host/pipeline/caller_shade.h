// A technique shaded from the caller's own light depth map and camera G-buffer (pn_shade): an engine has already
// drawn both, usually in hardware, and wants the filtering and the shading. The map replaces the fit and the draw
// (ShadowFrame::callerMap), the G-buffer is converted into penumbra's layout, and the technique's own stages
// (moments, blur, SAT, pyramids, the fits that measure the penumbrae) run on this object's buffers, kept across calls
// while the technique and its parameters stay the same. Every command goes to the context's queue in order; the
// fits that choose a radius or an exponent read a few bytes back, as in a frame of the Renderer.
#pragma once

#include <functional>
#include <glm/glm.hpp>
#include <map>
#include <memory>
#include <optional>
#include <string>

#include "host/cl/buffer.h"
#include "host/cl/context.h"
#include "host/scene/scene.h"
#include "host/stages/image_layout.h"
#include "host/techniques/technique.h"
#include "raster/rasterizer.h"

namespace penumbra {

// How a depth image stores its values.
enum class DepthStorage {
  Linear,  // the eye depth -z_eye (world units along the view axis)
  Window,  // a depth buffer's value d in [0, 1] as the projection and the viewport transform left it
};

// The projection's depth convention (which z_ndc a depth buffer's d = 0 and d = 1 are).
enum class NdcDepth {
  MinusOneToOne,  // OpenGL: d = z_ndc / 2 + 1/2
  ZeroToOne,      // Direct3D, Vulkan, OpenGL with glClipControl: d = z_ndc (reversed Z included)
};

// The light's depth map as the caller drew it: square, with the light's view and projection (world -> light eye ->
// clip, OpenGL's matrix conventions as glm holds them: -z_eye is depth, column vectors). A spot light's projection is
// a perspective one (w_c = -z_eye), a directional light's an orthographic one; x_c may depend on x_eye and z_eye, y_c
// on y_eye and z_eye (off-centre frusta are fine; LiSPSM-style warps are not). Texels must be square.
struct CallerLightMap {
  CallerImage depth;
  int size = 0;  // texels per side
  DepthStorage storage = DepthStorage::Window;
  NdcDepth ndc = NdcDepth::MinusOneToOne;
  glm::mat4 view{1.0f}, projection{1.0f};
  // The light-eye depths of the projection's near and far planes, as the caller built it (0 and 0: recovered from the
  // projection, to float round-off); the moment techniques normalise depths by this range.
  float depthNear = 0, depthFar = 0;
};

// The camera's G-buffer: width x height pixels, given as world positions (float4: xyz; w = 0 marks background) or as
// a depth buffer (Window storage in `ndc`'s convention, `clearDepth` marking background) with the inverse of
// the camera's view-projection; normals (float4 xyz, any length) are optional: without them each pixel's geometric
// normal is taken from its neighbours' positions.
struct CallerGBuffer {
  int width = 0, height = 0;
  std::optional<CallerImage> positions;
  std::optional<CallerImage> depth;
  glm::mat4 inverseViewProjection{1.0f};  // with `depth`
  NdcDepth ndc = NdcDepth::MinusOneToOne;
  // With `depth`: the value it was cleared to, which marks background (as do values beyond it and NaN): 1, or 0 with
  // reversed Z.
  float clearDepth = 1.0f;
  std::optional<CallerImage> normals;
};

class CallerShader {
 public:
  explicit CallerShader(Context& ctx);
  ~CallerShader();

  // Shades `technique` (one whose TechniqueInfo::callerMapRefusal is empty) with `params` for the light whose map is
  // `map` at the pixels of `gbuffer`, writing each pixel's visibility (0..1, 1 for background) into `visibility`
  // (gbuffer.width x gbuffer.height floats at its place). `light` gives the type (Spot or Directional) and the size
  // (radius; angularRadiusDeg); its position and direction are the map's view's. `sceneBounds` (the scene's box) scale
  // the thresholds of vssm and savsm as a Renderer's scene does; without it, the light's frustum between the map's near
  // and far planes stands in. Throws std::invalid_argument naming what cannot work before any command is enqueued;
  // then runs `beforeCommands` (may be empty: the C API's barrier on the caller's wait list) and enqueues.
  // Returns the provenance a Renderer's frame records for the light ("penumbra:light-fit", "penumbra:pcf-radius", ...).
  std::map<std::string, std::string> shade(const TechniqueInfo& technique, const Params& params, const Light& light,
                                           const CallerLightMap& map, const CallerGBuffer& gbuffer,
                                           const std::optional<Bounds>& sceneBounds, CallerImage& visibility,
                                           const std::function<void()>& beforeCommands = {});

 private:
  Context& ctx_;
  Rasterizer raster_;  // holds no triangles: ShadowFrame's, never drawn with a caller's map
  GBuffer gbuffer_;
  Buffer<float> visibility_;
  std::unique_ptr<Technique> technique_;
  const TechniqueInfo* info_ = nullptr;
};

// The names of the techniques that shade from a caller's map, comma-separated ("sm, pcf, ...").
std::string callerMapTechniques();

}  // namespace penumbra
