// Parsing at scale and at the edges of the ranges: deep node chains and wide JSON load (linear-time parsing, no
// recursion), limits are still enforced, and huge-but-finite or overflowed values are refused naming the element.
// Times are measured in docs/robustness.md, not asserted here.
#include <filesystem>
#include <fstream>
#include <string>

#include <gtest/gtest.h>

#include "host/scene/gltf_loader.h"
#include "host/scene/json_util.h"
#include "host/scene/scene_file.h"
#include "scene_test_util.h"
#include "tests/support/gltf_builder.h"
#include "tests/support/temp_dir.h"

namespace penumbra {
namespace scene_parse_scale_test {

namespace fs = std::filesystem;
using test::GltfBuilder;
using test::throwsWith;
using Json = nlohmann::json;

const std::vector<glm::vec3> kTriangle = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};

class ParseScale : public ::testing::Test {
 protected:
  // A glTF whose scene root is a chain of `depth` nodes, the last one's child the triangle's node 0.
  std::string chain(int depth, const std::string& name) {
    GltfBuilder b(kTriangle);
    Json& nodes = b.doc()["nodes"];
    for (int i = 1; i <= depth; ++i)
      nodes.push_back({{"children", {i < depth ? i + 1 : 0}}, {"translation", {0, 0, 1e-6}}});
    b.doc()["scenes"][0]["nodes"] = Json::array({1});
    return b.write(dir_, name);
  }
  std::string write(const std::string& name, const std::string& text) {
    std::ofstream(dir_ / name) << text;
    return (dir_ / name).string();
  }
  test::TempDir scratch_{"penumbra_parse_scale"};
  const fs::path dir_ = scratch_.path();
};

TEST_F(ParseScale, DeepNodeChainLoadsEveryLink) {
  const Scene scene = loadGltf(chain(200000, "chain"));
  ASSERT_EQ(scene.triangleCount(), 1u);
  EXPECT_NEAR(scene.positions[0].z, 200000 * 1e-6, 1e-3);  // every one of the 200,000 translations applied
}

TEST_F(ParseScale, WideArrayOfEmptyObjectsParsesWhole) {
  std::string text = "[";
  for (int i = 0; i < 300000; ++i) text += i ? ",{}" : "{}";
  text += "]";
  const Json doc = detail::parseJson("wide.json", text, true, uint64_t{1} << 24);
  EXPECT_EQ(doc.size(), 300000u);
}

TEST_F(ParseScale, LimitsStillHold) {
  const auto parse = [](const std::string& text, bool duplicates = true, uint64_t values = 1000) {
    return [=] { detail::parseJson("t.json", text, duplicates, values); };
  };
  EXPECT_NO_THROW(parse(std::string(65, '[') + std::string(65, ']'))());
  EXPECT_TRUE(throwsWith(parse(std::string(66, '[') + std::string(66, ']')), {"t.json", "nested deeper than 64"}));
  EXPECT_TRUE(throwsWith(parse(R"({"a": {"b": 1, "b": 2}})"), {"t.json", "duplicate key \"b\""}));
  EXPECT_NO_THROW(parse(R"({"a": {"b": 1}, "c": {"b": 2}})")());  // the same key in two objects
  EXPECT_NO_THROW(parse(R"({"b": 1, "b": 2})", false)());
  EXPECT_TRUE(throwsWith(parse("[1,2,3,4]", true, 4), {"more than 4 JSON values"}));
  EXPECT_TRUE(throwsWith(parse("[1,2,"), {"t.json", "invalid JSON", "parse error"}));
}

TEST_F(ParseScale, OverflowedIntegersAreNamed) {
  std::string path = GltfBuilder(kTriangle).write(dir_, "sparse");  // then a sparse on its POSITION accessor
  std::ifstream in(path);
  Json doc = Json::parse(in);
  doc["accessors"][0]["sparse"] = {{"count", 2147483648u},
                                   {"indices", {{"bufferView", 0}, {"componentType", 5125}}},
                                   {"values", {{"bufferView", 0}}}};
  path = write("sparse.gltf", doc.dump());
  EXPECT_TRUE(throwsWith([&] { loadGltf(path); },
                         {"sparse.gltf", "/accessors/0/sparse/count", "2147483648 is larger than 2147483647"}));
}

TEST_F(ParseScale, HugeFinitePositionsNameTheAccessor) {
  EXPECT_TRUE(throwsWith(
      [&] {
        loadGltf(GltfBuilder({{0, 0, 0}, {3e38f, 0, 0}, {0, 1, 0}}).write(dir_, "huge"));
      },
      {"huge.gltf", "accessor 0: POSITION 1", "outside +-1e+18"}));
  GltfBuilder scaled(kTriangle);
  scaled.doc()["nodes"][0]["scale"] = {1e30, 1, 1};
  EXPECT_TRUE(throwsWith([&] { loadGltf(scaled.write(dir_, "scaled")); },
                         {"scaled.gltf", "node 0 (mesh 0 primitive 0): world position", "outside +-1e+18"}));
}

TEST_F(ParseScale, SceneFileCoordinatesOutOfRangeNameTheField) {
  GltfBuilder(kTriangle).write(dir_, "tri");
  const std::string eye = write("eye.json", R"({"models": [{"path": "tri.gltf"}],
      "camera": {"eye": [1e308, 0, 0], "target": [0, 0, 0]}})");
  EXPECT_TRUE(throwsWith([&] { loadSceneFile(eye); }, {"eye.json", "/camera/eye", "outside +-1e+18"}));
  const std::string ground = write("ground.json", R"({"models": [{"path": "tri.gltf"}], "ground": {"y": -1e38}})");
  EXPECT_TRUE(throwsWith([&] { loadSceneFile(ground); }, {"ground.json", "/ground/y", "coordinate range"}));
}

}  // namespace scene_parse_scale_test
}  // namespace penumbra
