// Scenes with analytic shadows, shared by the technique and reference tests: a 2x2 square occluder 2 units above
// a 10x10 ground under a light 4 units up, so a point light's shadow on the ground is exactly |x|, |z| < 2.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>

#include "host/io/image.h"
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

// The hard shadow of squareOverPlane() under pointAbove() checked on a render (P.*, A, visibility.Y): ground
// pixels farther than `band` world units from the edge |x|, |z| = 2 must be within `tolerance` of 0 inside it
// and 1 outside; the occluder's own pixels are skipped.
struct HardEdgeCount {
  int shadowed = 0, lit = 0, wrong = 0;
};
inline HardEdgeCount checkHardEdge(const Image& image, float band, float tolerance) {
  const auto &vis = image.require("visibility.Y").data, &px = image.require("P.X").data,
             &py = image.require("P.Y").data, &pz = image.require("P.Z").data, &a = image.require("A").data;
  HardEdgeCount count;
  for (size_t i = 0; i < vis.size(); ++i) {
    if (a[i] == 0.0f || py[i] > 0.5f) continue;                            // background, or the occluder itself
    const float edge = std::max(std::abs(px[i]), std::abs(pz[i])) - 2.0f;  // < 0 inside the shadow
    if (std::abs(edge) < band) continue;
    const float expected = edge < 0 ? 0.0f : 1.0f;
    (expected == 0.0f ? count.shadowed : count.lit)++;
    count.wrong += std::abs(vis[i] - expected) > tolerance;
  }
  return count;
}

}  // namespace penumbra::test
