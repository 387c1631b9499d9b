// Where the camera and the light look: the camera's near/far fitted to the scene bounds, and the light's
// view (perspective for spot lights, orthographic for directional lights) fitted to what can matter: the
// receivers the camera sees (host/views/light_fit.h) and the casters between them and the light.
#pragma once

#include "host/views/light_fit.h"
#include "host/scene/scene.h"
#include "kernels/shared/light_view.h"
#include "raster/rasterizer.h"

namespace penumbra {

// The rows of `m` (glm, column-major) as LightViewGpu's row-major float4s (view, projection).
void setLightViewRows(pn_float4 rows[4], const glm::mat4& m);

// The camera's raster view (perspective or orthographic) with near/far fitted to the bounds (near clamped to
// far * 1e-4) and clipped to the camera's clipNear/clipFar; it culls the back faces of single-sided materials.
RasterView cameraView(const Camera& camera, const Bounds& bounds);

// The light's raster view (linear depth) for a square map of `size` texels, and the matching GPU struct.
struct LightView {
  RasterView raster;
  LightViewGpu gpu;
};
//
// Without receivers (nullptr or empty) the view covers the whole scene (directional) or the whole cone
// (spot). With receivers, x/y are cropped to the receivers' light-space box (never beyond the scene or the
// cone), squared, and widened so `marginTexels` texels of the final map lie around it on every side: a
// filter that reads up to that many texels from a receiver's own texel stays inside the map. The far plane
// is the deepest receiver (casters behind every receiver shadow nothing visible); the near plane keeps every
// caster between the light and the scene. Texel and depth units of the result are in `gpu`.
// `snapToTexels` (parallel splits' stability option): a cropped window's extent is rounded up to a step of
// 2^(1/8) relative to the full window and its centre to whole texels of the result, so a moving camera moves
// the map by whole texels and changes its texel size only in discrete steps (no shimmering edges).
// Its draws leave out the sides of solids that face away from the light (RasterView::cullSolidsFarSides).
LightView fitLightView(const Light& light, const Bounds& scene, int size, const ReceiverBounds* receivers = nullptr,
                       float marginTexels = 0.0f, bool snapToTexels = false);

// The light as the rasterizer's caster test sees it (RasterView::casterLight): the ball of a spot's disk or a point's
// sphere (a cube face's square spot keeps its point's centre and radius), or a sun's cone of directions.
RasterLight rasterLightOf(const Light& light);

// The part [ndcLo, ndcHi] (in base's NDC x, y) of base's window as a map of `size` texels: the crop matrix C
// (ndc' = s ndc + o mapping the part onto [-1, 1]^2, Zhang et al. 2006's) times base's projection, which keeps the
// rasterizer's separable form; texel and frustum widths scale with the part. Virtual shadow maps' tiles (fvsm).
LightView cropLightView(const LightView& base, glm::vec2 ndcLo, glm::vec2 ndcHi, int size);

}  // namespace penumbra
