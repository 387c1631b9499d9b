// Scenes with analytic shadows, shared by the technique and reference tests: a 2x2 square occluder 2 units above
// a 10x10 ground under a light 4 units up, so a point light's shadow on the ground is exactly |x|, |z| < 2.
#pragma once

#include <cstdint>

#include "host/scene/camera.h"
#include "host/scene/light.h"
#include "host/scene/scene.h"

namespace penumbra::test {

// A 10x10 ground at y = 0 and a 2x2 occluder at y = 2, both facing up.
inline Scene squareOverPlane() {
  Scene scene;
  auto quad = [&](float half, float y, uint32_t object) {
    const uint32_t base = static_cast<uint32_t>(scene.positions.size());
    for (glm::vec2 c : {glm::vec2(-1, -1), glm::vec2(1, -1), glm::vec2(1, 1), glm::vec2(-1, 1)}) {
      scene.positions.push_back({c.x * half, y, c.y * half});
      scene.normals.push_back({0, 1, 0});
    }
    scene.triangles.push_back({base, base + 2, base + 1});  // counter-clockwise seen from +Y
    scene.triangles.push_back({base, base + 3, base + 2});
    scene.objectIds.insert(scene.objectIds.end(), 2, object);
    scene.objectNames.push_back(object == 0 ? "ground" : "occluder");
  };
  quad(5.0f, 0.0f, 0);
  quad(1.0f, 2.0f, 1);
  return scene;
}

// Looks down at the ground from above and in front; 160x120.
inline Camera topDown() {
  Camera camera;
  camera.eye = {0.0f, 7.0f, 5.0f};
  camera.target = {0.0f, 0.0f, 0.0f};
  camera.width = 160;
  camera.height = 120;
  return camera;
}

// A point light at y = 4 above the occluder's centre: its edge |x| = 1 at y = 2 lands on |x| = 2 on the ground.
inline Light pointAbove() { return parseLight("spot:0,4,0:0,0,0:120"); }

}  // namespace penumbra::test
