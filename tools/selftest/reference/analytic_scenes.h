// Scenes with analytic shadows, shared by the technique and reference tests and `penumbra selftest`'s technique
// checks (tools/selftest/technique_checks.cpp): a 2x2 square occluder 2 units above a 10x10 ground under a light 4
// units up, so a point light's shadow on the ground is exactly |x|, |z| < 2; one frame of it through the Renderer, and
// each technique's margin on its hard edge. Free of GoogleTest: the selftest is compiled into the tool.
#pragma once

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "host/io/image.h"
#include "host/pipeline/renderer.h"
#include "host/scene/camera.h"
#include "host/scene/light.h"
#include "host/scene/procedural_mesh.h"
#include "host/scene/scene.h"
#include "host/techniques/registry.h"

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

// `scene` with a sliver just under the middle of its floor (10^-4 of its size below its bounds): a shadow map
// then keeps the floor's triangles, which may shadow the sliver (RasterView::casterLight leaves out only what shadows
// no point of the scene), so a lone plane can shadow itself, as tests of acne and its biases need. The floor hides the
// sliver from a camera and lights above it.
inline Scene withSliverBelow(Scene scene) {
  const Bounds b = scene.bounds();
  const glm::vec3 c = b.center();
  const float size = glm::length(b.max - b.min), y = b.min.y - 1e-4f * size, e = 1e-3f * size;
  detail::addTriangle(scene, 0, {c.x, y, c.z}, {c.x, y, c.z + e}, {c.x + e, y, c.z});
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
// What topDown()'s view of the ground holds beyond the bands: fewer pixels checked on either side than these means the
// render did not come out as the check assumes.
inline constexpr int kHardEdgeMinShadowed = 2000, kHardEdgeMinLit = 5000;
struct HardEdgeCount {
  int shadowed = 0, lit = 0, wrong = 0;
  float worstError = 0.0f;              // the largest |visibility - expected| among the pixels checked (NaN: infinite)
  std::vector<size_t> firstWrong = {};  // the first 8 wrong pixels' indices in the image (row 0 at the top)
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
    const float error = std::isnan(vis[i]) ? INFINITY : std::abs(vis[i] - expected);
    count.worstError = std::max(count.worstError, error);
    if (!(error <= tolerance) && count.wrong++ < 8) count.firstWrong.push_back(i);
  }
  return count;
}

// How far from the edge of checkHardEdge each technique may blur it (band, world units on the ground) and how near 0
// and 1 it must be beyond (tolerance), at map size 1024 with the camera of topDown(). Techniques.HardEdge...,
// VssmTechnique.HardEdge..., PssmTechniques.HardEdge... and `penumbra selftest`'s technique checks.
struct HardEdgeMargin {
  float band, tolerance;
};
inline HardEdgeMargin hardEdgeMargin(const std::string& technique) {
  // ~6 texels of 0.014 on the ground at map size 1024: covers the PCF/PCSS filter widths and the bias, vssm's
  // 0.5-texel kernels and bias, and pssm's PCF in each split.
  if (technique == "sm" || technique == "pcf" || technique == "pcss" || technique == "fvsm" || technique == "vssm" ||
      technique == "pssm")
    return {0.08f, 1e-6f};
  // izb is exact: only a pixel centre within rounding of the edge itself may land on either side.
  if (technique == "izb") return {1e-3f, 0.0f};
  // Moment techniques blur their moments (Gaussian taps reach 5 texels, plus the bilinear texel): 9 texels;
  // their umbra is only nearly 0 (Chebyshev with the minimum variance: ~1e-6; MSM's moment bias) and their
  // lit side nearly 1 where the Gaussian's far tail still sees the occluder. psvsm: the same blur on split 0.
  return {0.12f, 1e-3f};
}

// One frame through the whole pipeline: a fresh Renderer, the named technique at its defaults with `values` set on
// top (each validated like a CLI option).
using Values = std::map<std::string, std::string>;
inline RenderResult renderWith(Context& ctx, const Scene& scene, const Camera& camera, const Light& light,
                               const std::string& technique, const Values& values = {}) {
  const TechniqueInfo& info = findTechnique(technique);
  Params params(info.params);
  for (const auto& [name, value] : values) params.set(name, value);
  Renderer renderer(ctx, scene);
  return renderer.render(camera, light, info, params);
}

// What is wrong with a frame whatever the scene: a NaN in any channel ("NaN in P.X") or a visibility.Y value outside
// [0, 1] ("visibility 1.5"); empty when nothing is.
inline std::string imageDefect(const Image& image) {
  for (const ImageChannel& channel : image.channels())
    for (float v : channel.data)
      if (std::isnan(v)) return "NaN in " + channel.name;
  for (float v : image.require("visibility.Y").data)
    if (!(v >= 0.0f && v <= 1.0f)) return fmt::format("visibility {}", v);
  return {};
}

}  // namespace penumbra::test
