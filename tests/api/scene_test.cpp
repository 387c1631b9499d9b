// pn_scene_create: a scene of the caller's own triangle arrays through the C API and the C++ classes. A card above a
// ground under a directional light at 45 degrees: sm shadows exactly the ground the card hides from it (analytic),
// the card's transform moves the shadow, the scene's own lights are the default ones, and bad arrays are refused
// with the mesh and the element named.
#include <penumbra/penumbra.h>

#include <cmath>
#include <cstddef>
#include <cstring>
#include <penumbra/penumbra.hpp>
#include <string>
#include <vector>

#include "tests/api/caller_cl.h"

namespace penumbra::test {
namespace scene_test {

constexpr int kSize = 64;
// A 10 x 10 ground (y = 0) and a 2 x 2 card (y = 1), both facing +Y, counter-clockwise from above.
const std::vector<float> kGround = {-5, 0, -5, -5, 0, 5, 5, 0, 5, 5, 0, -5};
const std::vector<float> kCard = {-1, 1, -1, -1, 1, 1, 1, 1, 1, 1, 1, -1};
const std::vector<uint32_t> kQuad = {0, 1, 2, 0, 2, 3};

pn_mesh mesh(const std::vector<float>& positions, const float* transform = nullptr) {
  pn_mesh m;
  pn_mesh_init(&m);
  m.positions = positions.data(), m.vertex_count = positions.size() / 3;
  m.indices = kQuad.data(), m.triangle_count = kQuad.size() / 3;
  m.transform = transform;
  return m;
}

// sm visibility of the ground seen from above.
struct TopView {
  std::vector<float> visibility, px, py, pz;
  float at(float x, float z) const {  // the visibility of the ground pixel whose position is nearest (x, 0, z)
    size_t best = px.size();
    float nearest = INFINITY;
    for (size_t i = 0; i < px.size(); ++i)
      if (std::abs(py[i]) < 1e-3f && std::hypot(px[i] - x, pz[i] - z) < nearest)
        best = i, nearest = std::hypot(px[i] - x, pz[i] - z);
    EXPECT_LT(nearest, 0.2f) << "no ground pixel near (" << x << ", " << z << ")";
    return best < px.size() ? visibility[best] : NAN;
  }
};

TopView render(const Scene& scene) {
  Context context;
  Renderer renderer(context, scene);
  Camera camera = Camera::parse("0,20,0.001:0,0,0:30");
  camera.width = camera.height = kSize;
  Params params("sm");
  params.set("map-size", 512);
  const Frame frame = renderer.render(camera, params);
  auto take = [&](const char* name) {
    const float* data = frame.channel(name);
    return std::vector<float>(data, data + kSize * kSize);
  };
  return {take("visibility.Y"), take("P.X"), take("P.Y"), take("P.Z")};
}

TEST(ApiScene, CallersTrianglesCastExactShadows) {
  const std::vector<Light> sun = {Light::parse("dir:1,-1,0")};  // the card's shadow: x in [0, 2], z in [-1, 1]
  const Scene scene = Scene::fromMeshes({mesh(kGround), mesh(kCard)}, sun);
  EXPECT_EQ(scene.triangleCount(), 4u);
  ASSERT_EQ(scene.lights().size(), 1u);  // the scene's own light, named as a scene file's
  EXPECT_EQ(scene.lights()[0].name, "light0");
  const TopView plain = render(scene);
  EXPECT_EQ(plain.at(1.5f, 0), 0.0f);  // in the shadow, beside the card
  EXPECT_EQ(plain.at(1.5f, 3), 1.0f);
  EXPECT_EQ(plain.at(-3, 0), 1.0f);
  EXPECT_EQ(plain.at(4.5f, 0), 1.0f);

  const float shift[16] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 3, 0, 0, 1};  // column-major: x + 3
  const TopView moved = render(Scene::fromMeshes({mesh(kGround), mesh(kCard, shift)}, sun));
  EXPECT_EQ(moved.at(1.5f, 0), 1.0f);
  EXPECT_EQ(moved.at(4.5f, 0), 0.0f);  // the shadow moved with the card: x in [3, 5]
}

TEST(ApiScene, BadArraysAreRefusedByName) {
  pn_scene* scene = nullptr;
  const std::vector<uint32_t> outOfRange = {0, 1, 9};
  pn_mesh bad = mesh(kCard);
  bad.indices = outOfRange.data(), bad.triangle_count = 1, bad.name = "card";
  EXPECT_EQ(pn_scene_create(&bad, 1, nullptr, 0, &scene), PN_ERROR_SCENE);
  EXPECT_STREQ(pn_last_error_message(), "mesh 0 \"card\": triangle 0 index 2 is 9, out of range (vertex count 4)");
  const std::vector<float> nan = {0, 0, 0, NAN, 0, 0, 0, 0, 1};
  pn_mesh notFinite = mesh(nan);
  notFinite.triangle_count = 1;
  EXPECT_EQ(pn_scene_create(&notFinite, 1, nullptr, 0, &scene), PN_ERROR_SCENE);
  EXPECT_NE(std::string(pn_last_error_message()).find("mesh 0: position 1 is not finite"), std::string::npos);
  pn_mesh missing = mesh(kCard);
  missing.positions = nullptr;
  EXPECT_EQ(pn_scene_create(&missing, 1, nullptr, 0, &scene), PN_ERROR_INVALID_ARGUMENT);
  EXPECT_EQ(pn_scene_create(nullptr, 2, nullptr, 0, &scene), PN_ERROR_INVALID_ARGUMENT);
  pn_mesh unsized = mesh(kCard);  // a struct filled without pn_mesh_init
  unsized.size = 0;
  EXPECT_EQ(pn_scene_create(&unsized, 1, nullptr, 0, &scene), PN_ERROR_INVALID_ARGUMENT);
  EXPECT_NE(std::string(pn_last_error_message()).find("pn_scene_create: meshes[0]->size 0 is smaller"),
            std::string::npos)
      << pn_last_error_message();
  pn_scene_load_options options;
  pn_scene_load_options_init(&options);
  EXPECT_EQ(options.size, sizeof(pn_scene_load_options));
  options.size = 1;
  EXPECT_EQ(pn_scene_load("builtin:box", &options, &scene), PN_ERROR_INVALID_ARGUMENT);
  EXPECT_NE(std::string(pn_last_error_message()).find("(call pn_scene_load_options_init first)"), std::string::npos);
  EXPECT_EQ(scene, nullptr);
  PN_ASSERT_OK(pn_scene_create(nullptr, 0, nullptr, 0, &scene));  // empty: a frame sees nothing
  EXPECT_EQ(pn_scene_triangle_count(scene), 0u);
  pn_scene_release(scene);
}

// Cameras and lights carry their size like the settings structs: every call that reads or fills one refuses a struct
// pn_*_init did not prepare (and leaves it untouched), and a caller compiled against a later, larger struct keeps its
// own size and the fields past ours.
TEST(ApiScene, CamerasAndLightsCarryTheirSize) {
  pn_camera camera;
  pn_camera_init(&camera);
  EXPECT_EQ(camera.size, sizeof(pn_camera));
  pn_light light;
  pn_light_init(&light);
  EXPECT_EQ(light.size, sizeof(pn_light));
  pn_scene* scene = nullptr;
  PN_ASSERT_OK(pn_scene_load("builtin:box", nullptr, &scene));

  pn_camera unsized = camera;
  unsized.size = 0, unsized.width = 7;
  EXPECT_EQ(pn_scene_default_camera(scene, &unsized), PN_ERROR_INVALID_ARGUMENT);
  EXPECT_NE(std::string(pn_last_error_message())
                .find("pn_scene_default_camera: camera->size 0 is smaller than its first version's"),
            std::string::npos)
      << pn_last_error_message();
  EXPECT_NE(std::string(pn_last_error_message()).find("(call pn_camera_init first)"), std::string::npos);
  EXPECT_EQ(unsized.width, 7);  // untouched
  EXPECT_EQ(pn_camera_parse("0,1,5:0,0,0", &unsized), PN_ERROR_INVALID_ARGUMENT);
  pn_light unsizedLight = light;
  unsizedLight.size = 4;
  EXPECT_EQ(pn_light_parse("dir:0,-1,0", &unsizedLight), PN_ERROR_INVALID_ARGUMENT);
  EXPECT_EQ(pn_scene_framing_light(scene, &unsizedLight), PN_ERROR_INVALID_ARGUMENT);
  EXPECT_EQ(pn_scene_light(scene, 0, &unsizedLight), PN_ERROR_INVALID_ARGUMENT);
  pn_scene* lit = nullptr;
  EXPECT_EQ(pn_scene_create(nullptr, 0, &unsizedLight, 1, &lit), PN_ERROR_INVALID_ARGUMENT);
  EXPECT_NE(std::string(pn_last_error_message()).find("pn_scene_create: lights[0]->size 4 is smaller"),
            std::string::npos)
      << pn_last_error_message();
  EXPECT_EQ(lit, nullptr);

  // A later version's caller: its struct is longer, and nothing of it past ours is written.
  struct LaterCamera {
    pn_camera camera;
    float addedField;
  } later;
  pn_camera_init(&later.camera);
  later.camera.size = sizeof(LaterCamera), later.addedField = 42.0f;
  PN_ASSERT_OK(pn_scene_default_camera(scene, &later.camera));
  EXPECT_EQ(later.camera.size, sizeof(LaterCamera));
  EXPECT_EQ(later.addedField, 42.0f);
  PN_ASSERT_OK(pn_scene_default_camera(scene, &camera));
  EXPECT_EQ(std::memcmp(&later.camera.eye, &camera.eye, sizeof(pn_camera) - offsetof(pn_camera, eye)), 0);
  pn_scene_release(scene);
}

}  // namespace scene_test
}  // namespace penumbra::test
