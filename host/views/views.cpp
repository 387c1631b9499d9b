// Camera and light views: the camera fitted to the scene's bounds, the light to the visible receivers.
#include "host/views/views.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <glm/gtc/matrix_transform.hpp>

#include "host/scene/solids.h"

namespace penumbra {
namespace {

std::array<glm::vec3, 8> corners(const Bounds& b) {
  std::array<glm::vec3, 8> c;
  for (int i = 0; i < 8; ++i) c[i] = {i & 1 ? b.max.x : b.min.x, i & 2 ? b.max.y : b.min.y, i & 4 ? b.max.z : b.min.z};
  return c;
}

// Linear depth range (-z_eye) of the bounds seen through `view`, widened by 1% and kept positive.
void depthRange(const glm::mat4& view, const Bounds& bounds, float& zNear, float& zFar) {
  float lo = INFINITY, hi = -INFINITY;
  for (const glm::vec3& c : corners(bounds)) {
    const float d = -(view * glm::vec4(c, 1.0f)).z;
    lo = std::min(lo, d), hi = std::max(hi, d);
  }
  zFar = hi > 0 ? hi * 1.01f : 1.0f;  // everything behind the eye (or no geometry): any valid range
  zNear = std::isfinite(lo) ? std::max(lo * 0.99f, zFar * 1e-4f) : zFar * 1e-4f;
  if (!(zNear < zFar)) zNear = zFar * 1e-4f;
}


// Square box [center - extent/2, center + extent/2]^2 of the map in the light's x/y units.
struct MapWindow {
  glm::vec2 center;
  float extent;
};

// The receivers' box clamped to `full`, squared, and widened by `marginTexels` texels of the result:
// extent' = extent + 2 m extent' / size, so extent' = extent / (1 - 2 m / size). Falls back to `full` when
// there is nothing to crop to or the crop would not be smaller.
MapWindow cropWindow(const MapWindow& full, const ReceiverBounds* receivers, int size, float marginTexels,
                     bool snap) {
  if (receivers == nullptr || receivers->empty) return full;
  const glm::vec2 fullLo = full.center - 0.5f * full.extent, fullHi = full.center + 0.5f * full.extent;
  const glm::vec2 lo = glm::max(receivers->lo, fullLo), hi = glm::min(receivers->hi, fullHi);
  if (!(lo.x <= hi.x && lo.y <= hi.y)) return full;  // every receiver outside the cone: nothing is lit anyway
  const float fraction = 2.0f * std::max(marginTexels, 0.0f) / static_cast<float>(size);
  if (fraction >= 0.5f) return full;
  // A receiver box of zero size (one pixel, a line) still gets a map of a few texels' footprint.
  float extent = std::max({hi.x - lo.x, hi.y - lo.y, full.extent * 1e-4f}) / (1.0f - fraction);
  if (extent >= full.extent) return full;
  glm::vec2 center = 0.5f * (lo + hi);
  if (snap) {  // the snapped centre moves by at most half a texel: inside the margin of >= 1 texel
    extent = std::min(full.extent * std::exp2(std::ceil(8.0f * std::log2(extent / full.extent)) / 8.0f), full.extent);
    const float texel = extent / static_cast<float>(size);
    center = full.center + glm::round((center - full.center) / texel) * texel;
  }
  return {center, extent};
}

}  // namespace

void setLightViewRows(pn_float4 rows[4], const glm::mat4& m) {
  for (int r = 0; r < 4; ++r) rows[r] = {{m[0][r], m[1][r], m[2][r], m[3][r]}};
}

RasterView cameraView(const Camera& camera, const Bounds& sceneBounds) {
  const Bounds bounds = sceneBounds.orUnit();
  RasterView view;
  view.view = camera.view();
  float zNear, zFar;
  depthRange(view.view, bounds, zNear, zFar);
  // The file's own planes clip inside the fitted range; when nothing lies between them, their range as it is (an
  // infinite far plane, glTF's perspective without zfar: the near plane and as far again), so that the frame shows
  // what the file says, nothing, rather than the scene its near plane clips away.
  const float clipNear = std::max(zNear, camera.clipNear), clipFar = std::min(zFar, camera.clipFar);
  if (clipNear < clipFar) {
    zNear = clipNear, zFar = clipFar;
  } else if (camera.clipNear > 0.0f) {
    zNear = camera.clipNear, zFar = std::isfinite(camera.clipFar) ? camera.clipFar : 2.0f * camera.clipNear;
  }
  view.projection = camera.projection(zNear, zFar);
  view.width = camera.width;
  view.height = camera.height;
  view.depthMode = DepthMode::kViewZ;
  view.cullSingleSided = true;  // glTF's doubleSided false: the camera never sees such a triangle's back
  return view;
}

RasterLight rasterLightOf(const Light& light) {
  const LightExtent e = lightExtent(light);
  RasterLight r;
  r.directional = e.sun;
  r.position = e.centre, r.radius = std::max(e.radius, 0.0f);
  r.towards = e.towardSun, r.angularRadius = std::max(e.angularRadius, 0.0f);
  return r;
}

LightView fitLightView(const Light& light, const Bounds& sceneBounds, int size, const ReceiverBounds* receivers,
                       float marginTexels, bool snapToTexels) {
  const Bounds scene = sceneBounds.orUnit();
  LightView lv{};
  RasterView& raster = lv.raster;
  LightViewGpu& gpu = lv.gpu;
  raster.width = raster.height = size;
  raster.depthMode = DepthMode::kViewZ;
  raster.cullSolidsFarSides = true;  // the nearest surface along every ray of the map is the same
  raster.view = lightEyeMatrix(light, scene);
  float zNear, zFar;
  depthRange(raster.view, scene, zNear, zFar);
  if (receivers != nullptr && !receivers->empty && receivers->depthMax > 0.0f)
    zFar = std::max(std::min(zFar, receivers->depthMax * 1.01f), zNear * 1.0001f);
  MapWindow full;
  if (light.type == LightType::Spot) {
    full = {glm::vec2(0.0f), 2.0f * std::tan(glm::radians(light.fovDeg) * 0.5f)};
  } else {
    glm::vec2 lo(INFINITY), hi(-INFINITY);
    for (const glm::vec3& c : corners(scene)) {
      const glm::vec4 e = raster.view * glm::vec4(c, 1.0f);
      lo = glm::min(lo, glm::vec2(e)), hi = glm::max(hi, glm::vec2(e));
    }
    full = {0.5f * (lo + hi), std::max({hi.x - lo.x, hi.y - lo.y, 1e-6f}) * 1.01f};  // square texels
  }
  const MapWindow window = cropWindow(full, receivers, size, marginTexels, snapToTexels);
  const glm::vec2 lo = window.center - 0.5f * window.extent, hi = window.center + 0.5f * window.extent;
  if (light.type == LightType::Spot) {
    // An off-centre perspective frustum whose window at depth n spans the tangent box times n.
    raster.projection = glm::frustum(lo.x * zNear, hi.x * zNear, lo.y * zNear, hi.y * zNear, zNear, zFar);
    gpu.kind = LIGHT_KIND_SPOT;
    gpu.lightSize = light.radius;
  } else {
    raster.projection = glm::ortho(lo.x, hi.x, lo.y, hi.y, zNear, zFar);
    gpu.kind = LIGHT_KIND_DIRECTIONAL;
    gpu.lightSize = std::tan(glm::radians(light.angularRadiusDeg));
  }
  gpu.frustumWidth = window.extent;
  gpu.texelScale = window.extent / static_cast<float>(size);
  setLightViewRows(gpu.view, raster.view);
  setLightViewRows(gpu.projection, raster.projection);
  const glm::vec3 axis = light.axis();
  gpu.position = {{light.position.x, light.position.y, light.position.z, 1.0f}};
  gpu.axis = {{axis.x, axis.y, axis.z, 0.0f}};
  gpu.zNear = zNear;
  gpu.zFar = zFar;
  gpu.width = gpu.height = size;
  return lv;
}

LightView cropLightView(const LightView& base, glm::vec2 ndcLo, glm::vec2 ndcHi, int size) {
  LightView lv = base;
  const glm::vec2 scale = 2.0f / (ndcHi - ndcLo), offset = -(ndcHi + ndcLo) / (ndcHi - ndcLo);
  glm::mat4 crop(1.0f);
  crop[0][0] = scale.x, crop[1][1] = scale.y, crop[3][0] = offset.x, crop[3][1] = offset.y;
  lv.raster.projection = crop * base.raster.projection;
  lv.raster.width = lv.raster.height = size;
  lv.raster.scissor.reset();
  lv.raster.tileMask = nullptr;
  const float part = 0.5f * (ndcHi.x - ndcLo.x);  // square parts of square windows
  lv.gpu.frustumWidth = base.gpu.frustumWidth * part;
  lv.gpu.texelScale = lv.gpu.frustumWidth / static_cast<float>(size);
  lv.gpu.width = lv.gpu.height = size;
  setLightViewRows(lv.gpu.projection, lv.raster.projection);
  return lv;
}

}  // namespace penumbra
