// The Embree reference's alpha masks and sidedness, the same as the rasterizer's: filter functions on the scene's
// geometry that compute a hit's texture coordinate from Embree's barycentrics (u, v) and reject it where the
// material's alpha test fails (kernels/shared/alpha.h, the function the fine stage calls), for shadow rays
// (occlusion) and primary rays (intersection; these also reject back faces of single-sided materials, as the camera's
// G-buffer culls them).
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include <embree3/rtcore.h>

#include "host/scene/scene.h"
#include "kernels/shared/alpha.h"

namespace penumbra::reference {

class AlphaFilter {
 public:
  // Copies what the filters read; throws std::runtime_error when the scene needs filter functions and this Embree
  // build has none (RTC_DEVICE_PROPERTY_FILTER_FUNCTION_SUPPORTED).
  AlphaFilter(RTCDevice device, const Scene& scene);

  // Installs the filters on `geometry` (the scene's triangles in order) where the scene needs them.
  void attach(RTCGeometry geometry) const;

  // Whether triangle `t`'s surface is there at Embree's barycentrics (u, v): its material's alpha test passes.
  bool passes(uint32_t t, float u, float v) const;
  // Whether a ray along `direction` may hit triangle `t` from the side it meets: single-sided materials only front.
  bool faces(uint32_t t, float dx, float dy, float dz) const;

 private:
  static void occludedFilter(const RTCFilterFunctionNArguments* args);
  static void intersectFilter(const RTCFilterFunctionNArguments* args);

  std::vector<AlphaMaterial> materials_;               // per Scene::materials entry
  std::vector<int32_t> alphaMaterial_;                 // per triangle (scenes that may discard): material, or -1
  std::vector<std::array<glm::vec2, 3>> uvs_;          // per triangle (likewise): its vertices' texture coordinates
  std::vector<glm::vec3> singleSidedNormal_;           // per triangle (scenes with single-sided materials): its face
                                                       // normal when single-sided, else 0
  std::vector<uint8_t> texels_;                        // Scene::alphaTexels
};

}  // namespace penumbra::reference
