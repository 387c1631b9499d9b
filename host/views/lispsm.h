// Light-space perspective shadow maps (Wimmer, Scherzer, Purgathofer, "Light Space Perspective Shadow Maps",
// EGSR 2004): the body B (camera frustum slice clipped to the scene, extruded towards the light), the light space
// (y = light direction, z = view direction projected perpendicular to it), the perspective warp with Wimmer's n_opt,
// and the map window fitted to B; spot lights in their post-perspective space, where they are directional. Luksch
// (sec. 3, 6.5.1, 7.1) uses it alone and per split.
#pragma once

#include <string>

#include "host/views/views.h"
#include "host/scene/camera.h"

namespace penumbra {

// What the warp is fitted to. `nearDepth`/`farDepth`: the camera view-depth range the map serves (the visible range,
// or one split's C_s .. C_{s+1}); the body is the frustum between them.
struct LispsmInput {
  const Light& light;
  const Camera& camera;
  float nearDepth, farDepth;
  const Bounds& scene;
  const ReceiverBounds* receivers = nullptr;  // the visible receivers' light-eye box; nullptr: no crop
  int size = 0;                               // map texels per side
  float marginTexels = 0.0f;                  // texels of the final map kept around the body on every side
  float n = 0.0f;                             // warp distance in world units; 0: Wimmer's n_opt
};

// How the warp came out, for the output's header.
struct LispsmFit {
  bool warped = false;   // false: the body was empty (or degenerate) and the uniform fitLightView map was used
  float n = 0.0f;        // the warp distance used (world units; spot: post-perspective n back in world units)
  float nOpt = 0.0f;     // (z_n + sqrt(z_n z_f)) / sin(gamma) before the uniform limit
  float gammaDeg = 0.0f; // angle between the view and the light direction
  float texelMin = 0.0f, texelMax = 0.0f;  // world width of a texel over the body's footprint (longer side)
  std::string uniformBecause = "empty body";  // why, when !warped
  std::string describe() const;            // "lispsm n 12.5 (n_opt 12.5, gamma 63.4 deg), texel 0.01..0.05"
};

// Above this many times the body's depth along the warp axis, n is clamped: the warp is then uniform to within
// 3% ((1 + 1/64)^2 texel-size ratio over the map) and the float matrix stays well conditioned. As gamma -> 0
// (view along the light, the duelling frusta) n_opt -> infinity, so the map turns smoothly into the uniform one.
inline constexpr float kLispsmMaxNOverDepth = 64.0f;

// The warped light view: `raster.projection` is a general projective matrix (raster/rasterizer.h) over the light's
// eye space whose stored depth stays the light's linear depth; `gpu.warp` is LIGHT_WARP_PERSPECTIVE.
// Spot lights: B is also clipped to the uniform spot frustum P_L (fitLightView: cone or receiver crop, near and far
// planes) as planes, before any divide, so it lies in front of the light's near plane; its vertices go to
// post-perspective (x, y) = (P_L V_L p).xy / w, the warp W is built there as for a sun (the view direction that of
// the camera's central ray there, gamma the world angle between the view and the light's ray at the ray's point
// nearest B's centroid, n carried from world units by B's depth along the warp axis in both spaces), and the
// projection is W P_L with its z row on the light's near plane. `texelScale` is then the geometric mean over B's
// vertices of texel width / light depth (the spot unit); LispsmFit's texels are world widths. An empty body, or a
// spot warp that is not finite with B in front of its centre, falls back to fitLightView (warped = false).
LightView fitLispsmView(const LispsmInput& input, LispsmFit* fit = nullptr);

}  // namespace penumbra
