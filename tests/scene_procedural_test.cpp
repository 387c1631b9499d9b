// Built-in scenes: well formed (finite, unit normals, counter-clockwise fronts), closed meshes closed,
// expected bounds and parts, a camera and a soft light that see them, and parameter checking.
#include <algorithm>

#include <gtest/gtest.h>

#include "host/scene/load.h"
#include "host/scene/procedural.h"
#include "scene_test_util.h"

namespace penumbra {
namespace scene_procedural_test {

using test::throwsWith;

// Names of objects that are closed meshes (boxes) in the built-in scenes.
bool closedByName(const std::string& name) {
  return name == "box" || name.rfind("pole-", 0) == 0 || name.rfind("step-", 0) == 0;
}

class ProceduralScenes : public ::testing::TestWithParam<std::string> {};

TEST_P(ProceduralScenes, WellFormedClosedAndViewed) {
  const Scene s = makeProcedural(GetParam());
  ASSERT_GT(s.triangleCount(), 0u);
  EXPECT_TRUE(test::wellFormed(s));
  EXPECT_TRUE(test::windingMatchesNormals(s, 0.999f));  // flat faces: vertex normals equal face normals
  for (uint32_t id = 0; id < s.objectNames.size(); ++id)
    if (closedByName(s.objectNames[id])) {
      EXPECT_TRUE(test::closedObject(s, id));
    }
  ASSERT_EQ(s.cameras.size(), 1u);
  ASSERT_EQ(s.lights.size(), 1u);
  EXPECT_TRUE(s.lights[0].isArea()) << "built-in scenes have soft-shadowing lights";
  // The camera looks at the scene: the bounds' centre projects inside the image.
  const Camera& c = s.cameras[0];
  const glm::vec4 clip = c.projection(0.1f, 1000.0f) * c.view() * glm::vec4(s.bounds().center(), 1);
  EXPECT_GT(clip.w, 0.0f);
  EXPECT_LT(std::abs(clip.x / clip.w), 1.0f);
  EXPECT_LT(std::abs(clip.y / clip.w), 1.0f);
  // The light shines down onto the scene.
  EXPECT_LT(s.lights[0].axis().y, -0.5f);
}

INSTANTIATE_TEST_SUITE_P(Procedural, ProceduralScenes,
                         ::testing::Values("box", "stacked-planes", "poles", "staircase", "single-triangle", "plane",
                                           "cards"),
                         [](const auto& test_info) {
                           std::string n = test_info.param;
                           std::replace(n.begin(), n.end(), '-', '_');
                           return n;
                         });

TEST(Procedural, EveryListedSceneBuilds) {
  for (const ProceduralInfo& info : proceduralScenes())
    EXPECT_GT(makeProcedural(info.name).triangleCount(), 0u) << info.name;
}

// What a scene file checks its limits with before building: the same count as the scene built.
TEST(Procedural, TriangleCountMatchesTheBuiltScene) {
  for (const ProceduralInfo& info : proceduralScenes())
    EXPECT_EQ(proceduralTriangleCount(info.name), makeProcedural(info.name).triangles.size()) << info.name;
  for (const auto& [rows, columns] : {std::pair{1.0, 1.0}, {7.0, 3.0}, {40.0, 25.0}}) {
    const ProceduralParams params{{"rows", rows}, {"columns", columns}};
    EXPECT_EQ(proceduralTriangleCount("poles", params), makeProcedural("poles", params).triangles.size());
  }
  EXPECT_EQ(proceduralTriangleCount("poles", {{"rows", 1000}, {"columns", 1000}}), 12000002u);
  EXPECT_THROW(proceduralTriangleCount("poles", {{"rows", 1001}}), SceneError);
  EXPECT_THROW(proceduralTriangleCount("boxx"), SceneError);
}

TEST(Procedural, BoxRestsOnTheGround) {
  const Scene s = makeProcedural("box", {{"size", 2.0}});
  EXPECT_EQ(s.bounds().min, glm::vec3(-5, 0, -5));
  EXPECT_EQ(s.bounds().max, glm::vec3(5, 2, 5));
  EXPECT_EQ(s.objectNames, (std::vector<std::string>{"ground", "box"}));
  EXPECT_EQ(s.triangleCount(), 2u + 12u);
}

TEST(Procedural, StackedPlanesAreThreeLevels) {
  const Scene s = makeProcedural("stacked-planes", {{"gap", 0.5}});
  EXPECT_EQ(s.objectNames, (std::vector<std::string>{"ground", "plane-mid", "plane-high"}));
  std::vector<float> heights;
  for (size_t t = 0; t < s.triangleCount(); t += 2) heights.push_back(s.positions[s.triangles[t].x].y);
  EXPECT_EQ(heights, (std::vector<float>{0.0f, 0.5f, 1.0f}));
  for (const glm::vec3& n : s.normals) EXPECT_EQ(n, glm::vec3(0, 1, 0));
}

TEST(Procedural, CardsCarryAHoledAlphaTexture) {
  const Scene s = makeProcedural("cards", {{"count", 2}, {"holes", 2}, {"texels", 32}});
  EXPECT_EQ(s.objectNames, (std::vector<std::string>{"ground", "card-0", "card-1"}));
  ASSERT_EQ(s.materials.size(), 2u);
  const Material& m = s.materials[1];
  EXPECT_EQ(m.alphaMode, AlphaMode::kMask);
  EXPECT_TRUE(m.mayDiscard() && m.needsUvs() && m.doubleSided);
  EXPECT_EQ(s.materialIds, (std::vector<uint32_t>{0, 0, 1, 1, 1, 1}));
  ASSERT_EQ(s.alphaTextures.size(), 1u);
  EXPECT_EQ(s.alphaTexels.size(), 32u * 32u);
  EXPECT_EQ(s.uvs.size(), s.positions.size());
  // 2 x 2 holes of 16 texels: a hole's centre is transparent, the corners between holes opaque.
  EXPECT_EQ(s.alphaTexels[8 * 32 + 8], 0);
  EXPECT_EQ(s.alphaTexels[0], 255);
  EXPECT_EQ(s.alphaTexels[16 * 32 + 16], 255);
  EXPECT_NE(describeMaterials(s).find("1 MASK"), std::string::npos);
}

TEST(Procedural, PolesFieldHasLongDepthRange) {
  const Scene s = makeProcedural("poles", {{"rows", 3}, {"columns", 2}, {"height", 4}});
  EXPECT_EQ(s.objectNames.size(), 1u + 6u);
  EXPECT_EQ(s.bounds().max.y, 4.0f);
  const Scene big = makeProcedural("poles");
  EXPECT_GT(big.bounds().max.z - big.bounds().min.z, 40.0f);
}

TEST(Procedural, StaircaseUnderAPlate) {
  const Scene s = makeProcedural("staircase", {{"steps", 4}, {"rise", 0.5}, {"plate_gap", 1}});
  EXPECT_EQ(s.objectNames.back(), "plate");
  EXPECT_EQ(s.bounds().max.y, 4 * 0.5f + 1);
  EXPECT_EQ(s.objectNames.size(), 1u + 4u + 1u);
}

TEST(Procedural, SingleTriangleAndPlane) {
  EXPECT_EQ(makeProcedural("single-triangle").triangleCount(), 1u);
  const Scene plane = makeProcedural("plane", {{"size", 4}});
  EXPECT_EQ(plane.triangleCount(), 2u);
  EXPECT_EQ(plane.bounds().min, glm::vec3(-2, 0, -2));
  EXPECT_EQ(plane.lights[0].type, LightType::Directional);
}

TEST(Procedural, BadNamesAndParameters) {
  EXPECT_TRUE(throwsWith([] { makeProcedural("boxes"); }, {"unknown built-in scene", "box, stacked-planes"}));
  EXPECT_TRUE(throwsWith([] { makeProcedural("box", {{"sise", 1}}); }, {"unknown parameter \"sise\""}));
  EXPECT_TRUE(throwsWith([] { makeProcedural("box", {{"size", 0}}); }, {"size = 0 is outside"}));
  EXPECT_TRUE(throwsWith([] { makeProcedural("poles", {{"rows", 2.5}}); }, {"integers only"}));
  EXPECT_TRUE(throwsWith([] { makeProceduralFromSpec("box:size"); }, {"expected key=value"}));
  EXPECT_TRUE(throwsWith([] { makeProceduralFromSpec("box:size=x"); }, {"size: expected a number"}));
  EXPECT_TRUE(throwsWith([] { makeProceduralFromSpec("box:size=1,size=2"); }, {"given twice"}));
  EXPECT_TRUE(throwsWith([] { makeProceduralFromSpec("box:size=nan"); }, {"not a finite number"}));
}

TEST(Procedural, SpecWithParameters) {
  const Scene s = loadScene("builtin:poles:rows=2,columns=1");
  EXPECT_EQ(s.objectNames.size(), 3u);
}

}  // namespace scene_procedural_test
}  // namespace penumbra
