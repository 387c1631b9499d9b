// Camera and light views fitted to a scene's bounds.
#include "host/pipeline/views.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <glm/gtc/matrix_transform.hpp>

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
  zFar = hi > 0 ? hi * 1.01f : 1.0f;
  zNear = std::max(lo * 0.99f, zFar * 1e-4f);
}

void setRows(pn_float4 rows[4], const glm::mat4& m) {
  for (int r = 0; r < 4; ++r) rows[r] = {{m[0][r], m[1][r], m[2][r], m[3][r]}};
}

}  // namespace

RasterView cameraView(const Camera& camera, const Bounds& bounds) {
  RasterView view;
  view.view = camera.view();
  float zNear, zFar;
  depthRange(view.view, bounds, zNear, zFar);
  view.projection = camera.projection(zNear, zFar);
  view.width = camera.width;
  view.height = camera.height;
  view.depthMode = DepthMode::kViewZ;
  return view;
}

LightView fitLightView(const Light& light, const Bounds& bounds, int size) {
  LightView lv{};
  RasterView& raster = lv.raster;
  LightViewGpu& gpu = lv.gpu;
  raster.width = raster.height = size;
  raster.depthMode = DepthMode::kViewZ;
  const glm::vec3 axis = light.axis();
  float zNear, zFar;
  if (light.type == LightType::Spot) {
    raster.view = glm::lookAt(light.position, light.target, chooseUp(axis));
    depthRange(raster.view, bounds, zNear, zFar);
    const float fov = glm::radians(light.fovDeg);
    raster.projection = glm::perspective(fov, 1.0f, zNear, zFar);
    gpu.kind = LIGHT_KIND_SPOT;
    gpu.frustumWidth = 2.0f * std::tan(fov * 0.5f);
    gpu.texelScale = gpu.frustumWidth / static_cast<float>(size);
    gpu.lightSize = light.radius;
  } else {
    const float radius = std::max(bounds.radius(), 1e-6f);
    const glm::vec3 center = bounds.center();
    raster.view = glm::lookAt(center - axis * (2.0f * radius), center, chooseUp(axis));
    glm::vec2 lo(INFINITY), hi(-INFINITY);
    for (const glm::vec3& c : corners(bounds)) {
      const glm::vec4 e = raster.view * glm::vec4(c, 1.0f);
      lo = glm::min(lo, glm::vec2(e)), hi = glm::max(hi, glm::vec2(e));
    }
    const float extent = std::max(hi.x - lo.x, hi.y - lo.y) * 1.01f;  // square texels
    const glm::vec2 mid = 0.5f * (lo + hi);
    depthRange(raster.view, bounds, zNear, zFar);
    raster.projection =
        glm::ortho(mid.x - extent / 2, mid.x + extent / 2, mid.y - extent / 2, mid.y + extent / 2, zNear, zFar);
    gpu.kind = LIGHT_KIND_DIRECTIONAL;
    gpu.frustumWidth = extent;
    gpu.texelScale = extent / static_cast<float>(size);
    gpu.lightSize = std::tan(glm::radians(light.angularRadiusDeg));
  }
  setRows(gpu.view, raster.view);
  setRows(gpu.projection, raster.projection);
  gpu.position = {{light.position.x, light.position.y, light.position.z, 1.0f}};
  gpu.axis = {{axis.x, axis.y, axis.z, 0.0f}};
  gpu.zNear = zNear;
  gpu.zFar = zFar;
  gpu.width = gpu.height = size;
  return lv;
}

}  // namespace penumbra
