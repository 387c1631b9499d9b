// A scene of the caller's own arrays (host/scene/mesh_input.h): the same geometry as a built-in scene when given its
// arrays, transforms applied (normals by the inverse transpose, winding flipped by mirrors), missing normals made
// area-weighted, single-sided meshes given a single-sided material, lights named, and every bad input refused with
// the mesh and the element named.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <vector>

#include <glm/gtc/matrix_transform.hpp>

#include "host/scene/mesh_input.h"
#include "host/scene/procedural.h"
#include "scene_test_util.h"

namespace penumbra {
namespace scene_mesh_input_test {

using test::throwsWith;

// A unit quad in the XZ plane facing +Y: four vertices, two counter-clockwise triangles.
const std::vector<float> kQuad = {-1, 0, -1, -1, 0, 1, 1, 0, 1, 1, 0, -1};
const std::vector<uint32_t> kQuadIndices = {0, 1, 2, 0, 2, 3};

MeshInput quad() { return MeshInput{kQuad, {}, kQuadIndices, std::nullopt, "", true}; }
// An unnamed double-sided mesh of these arrays (every field given: -Wmissing-field-initializers).
MeshInput mesh(std::span<const float> positions, std::span<const float> normals, std::span<const uint32_t> indices,
               std::optional<glm::mat4> transform = std::nullopt) {
  return MeshInput{positions, normals, indices, transform, "", true};
}

Scene one(const MeshInput& mesh) { return meshScene(std::span<const MeshInput>(&mesh, 1), {}); }

TEST(MeshScene, EqualsABuiltInSceneGivenItsArrays) {
  const Scene box = makeProcedural("box");
  std::vector<float> positions, normals;
  for (size_t v = 0; v < box.positions.size(); ++v)
    for (int k = 0; k < 3; ++k) positions.push_back(box.positions[v][k]), normals.push_back(box.normals[v][k]);
  std::vector<uint32_t> indices;
  for (const glm::uvec3& t : box.triangles) indices.insert(indices.end(), {t.x, t.y, t.z});
  const Scene s = one(MeshInput{positions, normals, indices, std::nullopt, "box", true});
  EXPECT_EQ(s.positions, box.positions);
  EXPECT_EQ(s.normals, box.normals);
  EXPECT_EQ(s.triangles, box.triangles);
  EXPECT_EQ(s.objectNames, std::vector<std::string>{"box"});
  EXPECT_TRUE(s.materials.empty());  // double-sided and opaque: no materials, as the built-in scene
  EXPECT_TRUE(test::wellFormed(s));
}

TEST(MeshScene, TransformsNormalsAndWinding) {
  MeshInput mesh = quad();
  const Scene plain = one(mesh);
  for (const glm::vec3& n : plain.normals) EXPECT_EQ(n, glm::vec3(0, 1, 0));  // area-weighted from the triangles
  mesh.transform =
      glm::translate(glm::mat4(1.0f), glm::vec3(0, 2, 0)) * glm::scale(glm::mat4(1.0f), glm::vec3(2, 1, 1));
  const Scene moved = one(mesh);
  EXPECT_EQ(moved.positions[2], glm::vec3(2, 2, 1));
  EXPECT_TRUE(test::windingMatchesNormals(moved, 0.999f));
  mesh.transform = glm::scale(glm::mat4(1.0f), glm::vec3(1, -1, 1));  // a mirror: the quad now faces -Y
  const Scene mirrored = one(mesh);
  EXPECT_EQ(mirrored.normals[0], glm::vec3(0, -1, 0));
  EXPECT_TRUE(test::windingMatchesNormals(mirrored, 0.999f));
}

TEST(MeshScene, ObjectsMaterialsAndLights) {
  MeshInput single = quad();
  single.doubleSided = false;
  single.name = "floor";
  const std::vector<MeshInput> meshes = {quad(), single};
  Light a, b;
  const Scene s = meshScene(meshes, {a, b});
  EXPECT_EQ(s.objectNames, (std::vector<std::string>{"mesh 0", "floor"}));
  EXPECT_EQ(s.triangleCount(), 4u);
  ASSERT_EQ(s.materials.size(), 2u);  // the double-sided part's plain material, then the single-sided one
  EXPECT_TRUE(s.materialOf(0)->doubleSided);
  EXPECT_FALSE(s.materialOf(3)->doubleSided);
  ASSERT_EQ(s.lights.size(), 2u);
  EXPECT_EQ(s.lights[0].name, "light0");
  EXPECT_EQ(s.lights[1].name, "light1");
  EXPECT_EQ(meshScene(std::span<const MeshInput>(), {}).triangleCount(), 0u);  // empty: renders as nothing seen
}

TEST(MeshScene, BadInputNamesTheMeshAndTheElement) {
  const std::vector<float> nan = {0, 0, 0, std::numeric_limits<float>::quiet_NaN(), 0, 0, 0, 0, 1};
  const std::vector<float> huge = {0, 0, 0, 3e38f, 0, 0, 0, 0, 1};
  const std::vector<uint32_t> tri = {0, 1, 2}, outOfRange = {0, 1, 7}, two = {0, 1};
  const std::vector<float> eight = {0, 0, 0, 1, 0, 0, 0, 0};
  MeshInput named{kQuad, {}, outOfRange, std::nullopt, "rock", true};
  EXPECT_TRUE(
      throwsWith([&] { one(named); }, {"mesh 0 \"rock\": triangle 0 index 2 is 7, out of range (vertex count 4)"}));
  EXPECT_TRUE(throwsWith([&] { one(mesh(nan, {}, tri)); }, {"mesh 0: position 1 is not finite"}));
  EXPECT_TRUE(throwsWith([&] { one(mesh(eight, {}, tri)); }, {"8 position floats are not 3 per vertex"}));
  EXPECT_TRUE(throwsWith([&] { one(mesh(kQuad, {}, two)); }, {"2 indices are not 3 per triangle"}));
  EXPECT_TRUE(throwsWith([&] { one(mesh(kQuad, eight, kQuadIndices)); }, {"8 normal floats for 4 vertices"}));
  const MeshInput scaled = mesh(huge, {}, tri, glm::scale(glm::mat4(1.0f), glm::vec3(10.0f)));
  EXPECT_TRUE(throwsWith([&] { one(scaled); }, {"position 1 is not finite after the transform"}));
  glm::mat4 bad(1.0f);
  bad[3][1] = std::numeric_limits<float>::infinity();
  EXPECT_TRUE(throwsWith([&] { one(mesh(kQuad, {}, kQuadIndices, bad)); },
                         {"transform element [3][1] (column, row) is not finite"}));
  LoadOptions limits;
  limits.maxTriangles = 1;
  const MeshInput q = quad();
  EXPECT_TRUE(throwsWith([&] { meshScene(std::span<const MeshInput>(&q, 1), {}, limits); },
                         {"2 triangles and 4 vertices, over the limits of 1"}));
}

}  // namespace scene_mesh_input_test
}  // namespace penumbra
