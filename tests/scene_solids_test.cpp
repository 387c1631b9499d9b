// The scene's solids (host/scene/solids.h): which triangle groups close a volume and which side of each triangle is
// out, on boxes split at their edges (as glTF splits vertices at seams), turned inside out, opened, doubled, sheets
// and alpha-tested; and which triangles face away from a spot, sphere or sun light.
#include <gtest/gtest.h>

#include <algorithm>

#include "host/scene/procedural_mesh.h"
#include "host/scene/solids.h"

namespace penumbra {
namespace scene_solids_test {

using detail::addBox;
using detail::addObject;
using detail::addQuad;

// Triangles [first, end) of `scene` wound the other way.
void turnInsideOut(Scene& scene, size_t first) {
  for (size_t t = first; t < scene.triangles.size(); ++t) std::swap(scene.triangles[t].y, scene.triangles[t].z);
}

Scene oneBox() {
  Scene scene;
  addBox(scene, addObject(scene, "box"), glm::vec3(-1.0f), glm::vec3(1.0f));
  return scene;
}

// Every triangle of the box bounds solid 0, its outer plane the box's face, pointing out of the box.
void expectOutwardBox(const Scene& scene, const Solids& solids) {
  ASSERT_EQ(solids.bounds.size(), 1u);
  EXPECT_EQ(solids.triangles, 12u);
  for (size_t t = 0; t < 12; ++t) {
    EXPECT_EQ(solids.solidOf[t], 0) << t;
    const glm::uvec3 v = scene.triangles[t];
    const glm::vec3 centroid = (scene.positions[v.x] + scene.positions[v.y] + scene.positions[v.z]) / 3.0f;
    const glm::vec3 n(solids.outerPlane[t]);
    EXPECT_NEAR(glm::length(n), 1.0f, 1e-6f) << t;
    EXPECT_GT(glm::dot(n, centroid), 0.3f) << t;            // away from the centre
    EXPECT_NEAR(solids.outerPlane[t].w, 1.0f, 1e-6f) << t;  // every face lies 1 from the centre
  }
}

TEST(SceneSolids, ABoxSplitAtItsEdgesIsOneSolid) {
  const Scene scene = oneBox();
  ASSERT_EQ(scene.positions.size(), 24u);  // four vertices per face
  expectOutwardBox(scene, findSolids(scene));
}

TEST(SceneSolids, ABoxTurnedInsideOutKeepsItsOutside) {
  Scene scene = oneBox();
  turnInsideOut(scene, 0);
  expectOutwardBox(scene, findSolids(scene));
}

TEST(SceneSolids, OpenDoubledSheetAndAlphaTestedGroupsBoundNone) {
  Scene open = oneBox();
  open.triangles.pop_back();
  EXPECT_TRUE(findSolids(open).bounds.empty());

  Scene doubled = oneBox();  // a face drawn twice the same way: three triangles on its edges
  doubled.triangles.push_back(doubled.triangles.front());
  EXPECT_TRUE(findSolids(doubled).bounds.empty());

  Scene sheet;  // a quad and its back face on the same four vertices: closed, but no volume to tell its outside by
  const uint32_t object = addObject(sheet, "sheet");
  addQuad(sheet, object, {-1, 0, -1}, {-1, 0, 1}, {1, 0, 1}, {1, 0, -1});
  sheet.triangles.push_back({0, 2, 1});
  sheet.triangles.push_back({0, 3, 2});
  EXPECT_TRUE(findSolids(sheet).bounds.empty());

  Scene masked = oneBox();
  Material cutout = plainMaterial();
  cutout.alphaMode = AlphaMode::kMask;
  cutout.baseAlpha = 0.25f;  // below the cutoff: may discard
  masked.materials = {cutout};
  masked.materialIds.assign(masked.triangles.size(), 0);
  EXPECT_TRUE(findSolids(masked).bounds.empty());

  Scene outOfRange = oneBox();  // no solids, no read past the positions: the rasterizer's upload names the index
  outOfRange.triangles[3].z = 1000;
  const Solids none = findSolids(outOfRange);
  EXPECT_TRUE(none.bounds.empty());
  EXPECT_EQ(none.solidOf.size(), outOfRange.triangles.size());

  Scene nonFinite = oneBox();  // a NaN vertex: no volume to trust
  nonFinite.positions[0] = glm::vec3(NAN);
  EXPECT_TRUE(findSolids(nonFinite).bounds.empty());

  Scene repeated = oneBox();  // two vertices of one triangle at one position
  repeated.positions[repeated.triangles[0].y] = repeated.positions[repeated.triangles[0].x];
  EXPECT_TRUE(findSolids(repeated).bounds.empty());
}

TEST(SceneSolids, SeparateBoxesAreSeparateSolidsBesideOpenGeometry) {
  Scene scene = oneBox();
  addBox(scene, addObject(scene, "second"), {3, 0, 0}, {4, 2, 1});
  const uint32_t ground = addObject(scene, "ground");
  addQuad(scene, ground, {-5, -1, -5}, {-5, -1, 5}, {5, -1, 5}, {5, -1, -5});
  const Solids solids = findSolids(scene);
  ASSERT_EQ(solids.bounds.size(), 2u);
  EXPECT_EQ(solids.triangles, 24u);
  EXPECT_NE(solids.solidOf[0], solids.solidOf[12]);
  EXPECT_EQ(solids.solidOf[24], Solids::kNone);
  EXPECT_EQ(solids.solidOf[25], Solids::kNone);
  EXPECT_FALSE(facesAwayFromLight(solids, 24, lightExtent(parseLight("spot:0,10,0:0,0,0:60:0.5"))));
}

// The triangles of faces whose outer side no point of the light sees.
std::vector<glm::vec3> awayNormals(const Solids& solids, const Light& light) {
  std::vector<glm::vec3> normals;
  const LightExtent extent = lightExtent(light);
  for (size_t t = 0; t < solids.solidOf.size(); ++t)
    if (facesAwayFromLight(solids, t, extent)) normals.push_back(glm::round(glm::vec3(solids.outerPlane[t])));
  return normals;
}

TEST(SceneSolids, FacesAwayFromTheWholeLightOnly) {
  const Solids solids = findSolids(oneBox());
  const auto count = [](const std::vector<glm::vec3>& normals, glm::vec3 n) {
    return std::count(normals.begin(), normals.end(), n);
  };
  // A disk of radius 0.5 straight above: it sees only the top face (the sides' planes have it behind them).
  const std::vector<glm::vec3> small = awayNormals(solids, parseLight("spot:0,10,0:0,0,0:60:0.5"));
  EXPECT_EQ(small.size(), 10u);
  EXPECT_EQ(count(small, {0, 1, 0}), 0);
  EXPECT_EQ(count(small, {0, -1, 0}), 2);
  // Radius 2 reaches past the sides' planes: only the bottom faces away from all of it.
  const std::vector<glm::vec3> wide = awayNormals(solids, parseLight("spot:0,10,0:0,0,0:60:2"));
  EXPECT_EQ(wide.size(), 2u);
  EXPECT_EQ(count(wide, {0, -1, 0}), 2);
  // A sphere light of the same reach, beside the box.
  EXPECT_EQ(awayNormals(solids, parseLight("point:10,0,0:0.5")).size(), 10u);
  // A light inside the box, or whose ball reaches into its box, faces every side: nothing is left out.
  EXPECT_TRUE(awayNormals(solids, parseLight("spot:0,0.5,0:0,-1,0:60:0.2")).empty());
  EXPECT_TRUE(awayNormals(solids, parseLight("spot:0,1.4,0:0,0,0:60:0.5")).empty());
  // A sun of 5 degrees overhead: the bottom only; tilted 30 degrees towards +x, the bottom and the -x side.
  Light sun;
  sun.type = LightType::Directional;
  sun.direction = {0, -1, 0};
  sun.angularRadiusDeg = 5.0f;
  EXPECT_EQ(awayNormals(solids, sun).size(), 2u);
  sun.direction = glm::normalize(glm::vec3(-0.5f, -0.866f, 0.0f));
  const std::vector<glm::vec3> tilted = awayNormals(solids, sun);
  EXPECT_EQ(tilted.size(), 4u);
  EXPECT_EQ(count(tilted, {-1, 0, 0}), 2);  // the sun lies towards +x: the -x side faces away
  // A sun grazing the top face (4 degrees above its plane, 5 wide) sees it.
  sun.direction = glm::normalize(glm::vec3(1.0f, -0.07f, 0.0f));
  EXPECT_EQ(count(awayNormals(solids, sun), {0, 1, 0}), 0);
}

}  // namespace scene_solids_test
}  // namespace penumbra
