// Embree filter functions for alpha-tested and single-sided materials. Embree's hit is (1 - u - v) p0 + u p1 + v p2
// over the triangle's vertices in index order, so the texture coordinate interpolates the same way.
#include "tools/reference/alpha_filter.h"

#include <stdexcept>

#include "tools/reference/embree_api.h"

namespace penumbra::reference {

AlphaFilter::AlphaFilter(RTCDevice device, const Scene& scene) {
  if (scene.materials.empty()) return;
  for (const Material& m : scene.materials) materials_.push_back(alphaMaterial(m, scene.alphaTextures));
  bool alpha = false, sided = false;
  for (uint32_t id : scene.materialIds)
    alpha = alpha || scene.materials[id].mayDiscard(), sided = sided || !scene.materials[id].doubleSided;
  if (alpha && !embree().rtcGetDeviceProperty(device, RTC_DEVICE_PROPERTY_FILTER_FUNCTION_SUPPORTED))
    throw std::runtime_error(
        "reference: this Embree build has no filter functions, which the scene's alpha-tested materials need");
  const size_t n = scene.triangles.size();
  if (alpha) alphaMaterial_.assign(n, -1), uvs_.assign(n, {}), texels_ = scene.alphaTexels;
  if (sided) singleSidedNormal_.assign(n, glm::vec3(0.0f));
  for (size_t t = 0; t < n; ++t) {
    const Material& m = scene.materials[scene.materialIds[t]];
    const glm::uvec3 tri = scene.triangles[t];
    if (alpha && m.mayDiscard()) {
      alphaMaterial_[t] = static_cast<int32_t>(scene.materialIds[t]);
      for (int k = 0; k < 3; ++k) uvs_[t][k] = scene.uvs.empty() ? glm::vec2(0.0f) : scene.uvs[tri[k]];
    }
    if (sided && !m.doubleSided)
      singleSidedNormal_[t] = glm::cross(scene.positions[tri[1]] - scene.positions[tri[0]],
                                         scene.positions[tri[2]] - scene.positions[tri[0]]);
  }
}

void AlphaFilter::attach(RTCGeometry geometry) const {
  if (alphaMaterial_.empty() && singleSidedNormal_.empty()) return;
  embree().rtcSetGeometryUserData(geometry, const_cast<AlphaFilter*>(this));  // the filters only read it
  if (!alphaMaterial_.empty()) embree().rtcSetGeometryOccludedFilterFunction(geometry, &AlphaFilter::occludedFilter);
  embree().rtcSetGeometryIntersectFilterFunction(geometry, &AlphaFilter::intersectFilter);
}

bool AlphaFilter::passes(uint32_t t, float u, float v) const {
  if (alphaMaterial_.empty() || alphaMaterial_[t] < 0) return true;
  const std::array<glm::vec2, 3>& uv = uvs_[t];
  const glm::vec2 at = (1.0f - u - v) * uv[0] + u * uv[1] + v * uv[2];
  return alphaPasses(&materials_[static_cast<size_t>(alphaMaterial_[t])], texels_.data(), at.x, at.y) != 0;
}

bool AlphaFilter::faces(uint32_t t, float dx, float dy, float dz) const {
  if (singleSidedNormal_.empty()) return true;
  const glm::vec3 n = singleSidedNormal_[t];
  return n == glm::vec3(0.0f) || glm::dot(n, glm::vec3(dx, dy, dz)) < 0.0f;
}

void AlphaFilter::occludedFilter(const RTCFilterFunctionNArguments* args) {
  const auto* self = static_cast<const AlphaFilter*>(args->geometryUserPtr);
  for (unsigned i = 0; i < args->N; ++i)
    if (args->valid[i] == -1 && !self->passes(RTCHitN_primID(args->hit, args->N, i), RTCHitN_u(args->hit, args->N, i),
                                              RTCHitN_v(args->hit, args->N, i)))
      args->valid[i] = 0;
}

void AlphaFilter::intersectFilter(const RTCFilterFunctionNArguments* args) {
  const auto* self = static_cast<const AlphaFilter*>(args->geometryUserPtr);
  for (unsigned i = 0; i < args->N; ++i) {
    if (args->valid[i] != -1) continue;
    const uint32_t t = RTCHitN_primID(args->hit, args->N, i);
    const bool front = self->faces(t, RTCRayN_dir_x(args->ray, args->N, i), RTCRayN_dir_y(args->ray, args->N, i),
                                   RTCRayN_dir_z(args->ray, args->N, i));
    if (!front || !self->passes(t, RTCHitN_u(args->hit, args->N, i), RTCHitN_v(args->hit, args->N, i)))
      args->valid[i] = 0;
  }
}

}  // namespace penumbra::reference
