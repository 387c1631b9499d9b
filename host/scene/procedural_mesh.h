// Building blocks for procedural geometry: objects, flat quads and triangles, closed axis-aligned boxes
// and ground quads, all counter-clockwise seen from the side their normal points to. Added to a scene that has
// materials (or texture coordinates), they keep Scene::materialIds (the plain material) and Scene::uvs (zeros) in
// step.
#pragma once

#include <cstdint>
#include <string>

#include <glm/glm.hpp>

#include "host/scene/scene.h"

namespace penumbra::detail {

// Adds an object name and returns its id.
uint32_t addObject(Scene& scene, std::string name);

// A flat triangle / quad (a, b, c, d) with its face normal; counter-clockwise from the front.
void addTriangle(Scene& scene, uint32_t object, const glm::vec3& a, const glm::vec3& b, const glm::vec3& c);
void addQuad(Scene& scene, uint32_t object, const glm::vec3& a, const glm::vec3& b, const glm::vec3& c,
             const glm::vec3& d);

// A quad (a, b, c, d) with texture coordinates (0, 0), (0, 1), (1, 1), (1, 0) at its corners and material `material`
// of the scene (a card's alpha texture spans it once).
void addTexturedQuad(Scene& scene, uint32_t object, uint32_t material, const glm::vec3& a, const glm::vec3& b,
                     const glm::vec3& c, const glm::vec3& d);

// A closed box [min, max]: 6 outward faces, 24 vertices, flat normals.
void addBox(Scene& scene, uint32_t object, const glm::vec3& min, const glm::vec3& max);

// A horizontal quad at height y over [x0, x1] x [z0, z1], facing +Y.
void addHorizontalQuad(Scene& scene, uint32_t object, float x0, float x1, float z0, float z1, float y);

// The ground under `models` for scene files: a +Y quad named "ground" at `y` (default: the models' min y)
// reaching margin * max(width, depth) of the models beyond their bounds on every side.
void addGroundPlane(Scene& scene, const Bounds& models, float margin, float y);

}  // namespace penumbra::detail
