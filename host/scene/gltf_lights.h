// KHR_lights_punctual: every light instance of the default scene in world space (glTF lights shine down their
// node's local -Z), validated, with the soft-light size penumbra reads from the light's "extras".
#pragma once

#include <vector>

#include "host/scene/gltf_accessor.h"
#include "host/scene/gltf_nodes.h"
#include "host/scene/light.h"

namespace penumbra::detail {

// One Light per node (in `instances`' order) that references a light: spot (position, direction, 2 x
// outerConeAngle as fovDeg, 2 x innerConeAngle as innerFovDeg, range), directional (direction) and point
// (position, range). Sizes come from extras {"penumbra": {"radius": R}} (spot and point, metres, >= 0) or
// {"penumbra": {"angular_radius_deg": A}} (directional, [0, 45)); node scale changes no light property, as the
// extension says. Named after the light, else its node, else "light<K>" (K: the light's index), then made unique
// and channel-safe. Throws SceneError "FILE: light K ...: ..." for out-of-range cones, ranges and sizes and for
// node transforms that leave no finite direction.
std::vector<Light> readLights(const GltfContext& ctx, const std::vector<NodeInstance>& instances);

}  // namespace penumbra::detail
