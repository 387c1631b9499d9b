// The cube faces of point lights (kernels/shared/cube.h, kernels/cube.cl, host/views/cube.h): the face rule on the
// host and on the device against its definition (tools/selftest/reference/cube_ref.h) for adversarial directions (axes,
// diagonals and other exact ties, signed zeros, NaN, infinities, subnormals) and random ones; every direction lies in
// its face's square; each face spot's light eye is the face's frame; the face G-buffer and the copy against
// references.
#include "host/views/cube.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <glm/gtc/matrix_access.hpp>
#include <limits>
#include <random>
#include <vector>

#include "host/views/light_fit.h"
#include "tests/support/cl_test.h"
#include "tools/selftest/reference/cube_ref.h"

namespace penumbra {
namespace cube_test {

constexpr float kNan = std::numeric_limits<float>::quiet_NaN();
constexpr float kInf = std::numeric_limits<float>::infinity();

using ref::adversarialDirections;
using ref::randomDirections;

TEST(CubeFaceRule, MatchesItsDefinitionOnTheHost) {
  std::vector<glm::vec3> all = adversarialDirections();
  for (const glm::vec3& v : randomDirections(20000, 7)) all.push_back(v);
  for (const glm::vec3& d : all) {
    const int face = cubeFaceOf(d);
    ASSERT_EQ(face, ref::cubeFace(d.x, d.y, d.z)) << d.x << " " << d.y << " " << d.z;
    ASSERT_TRUE(face >= 0 && face < CUBE_FACES);
  }
  // The tie rule and the special cases as documented in kernels/shared/cube.h.
  EXPECT_EQ(cubeFaceOf({1, 1, 0}), CUBE_FACE_POS_X);
  EXPECT_EQ(cubeFaceOf({1, 1, 1}), CUBE_FACE_POS_X);
  EXPECT_EQ(cubeFaceOf({-1, -1, -1}), CUBE_FACE_NEG_X);
  EXPECT_EQ(cubeFaceOf({0, -1, 1}), CUBE_FACE_NEG_Y);
  EXPECT_EQ(cubeFaceOf({0, 0, -1}), CUBE_FACE_NEG_Z);
  EXPECT_EQ(cubeFaceOf({-0.0f, 0, 0}), CUBE_FACE_POS_X);
  EXPECT_EQ(cubeFaceOf({0, -0.0f, -0.0f}), CUBE_FACE_POS_X);
  EXPECT_EQ(cubeFaceOf({0, 0, 0}), CUBE_FACE_POS_X);
  EXPECT_EQ(cubeFaceOf({kNan, -5, 0}), CUBE_FACE_POS_X);
  EXPECT_EQ(cubeFaceOf({0, 0, kNan}), CUBE_FACE_POS_X);
  EXPECT_EQ(cubeFaceOf({kInf, -kInf, 0}), CUBE_FACE_POS_X);
  EXPECT_EQ(cubeFaceOf({1, -kInf, kInf}), CUBE_FACE_NEG_Y);
}

TEST(CubeFaceRule, EveryDirectionLiesInItsFacesSquareAndStrictlyInsideOnlyThere) {
  for (const glm::vec3& d : randomDirections(20000, 11)) {
    const int face = cubeFaceOf(d);
    ASSERT_TRUE(cube_in_window(d.x, d.y, d.z, face, 1.0f)) << d.x << " " << d.y << " " << d.z;
    const glm::vec3 a = glm::abs(d);
    const bool tie = a.x == a.y || a.y == a.z || a.x == a.z;
    int squares = 0;  // closed 90-degree squares holding d: one, or several on an edge or corner
    for (int f = 0; f < CUBE_FACES; ++f) squares += cube_in_window(d.x, d.y, d.z, f, 1.0f);
    if (!tie) {
      ASSERT_EQ(squares, 1) << d.x << " " << d.y << " " << d.z;
    }
  }
}

TEST(CubeFaceRule, EachFaceSpotsLightEyeIsTheFacesFrame) {
  const float tangent = cube_window_tangent(16.0f, 512);
  EXPECT_NEAR(tangent, 1.0f / (1.0f - 32.0f / 512.0f), 1e-6f);
  EXPECT_EQ(cube_window_tangent(1e6f, 512), 2.0f);  // at most a quarter of the map on each side
  EXPECT_EQ(cube_window_tangent(-3.0f, 512), 1.0f);
  for (const glm::vec3 position : {glm::vec3(0.3f, 4, -1), glm::vec3(1e6f, -3e5f, 7)}) {
    Light point;
    point.type = LightType::Point, point.position = position, point.radius = 0.25f, point.name = "Bulb";
    for (int face = 0; face < CUBE_FACES; ++face) {
      const Light spot = cubeFaceLight(point, face, tangent);
      EXPECT_EQ(spot.type, LightType::Spot);
      EXPECT_EQ(spot.radius, 0.25f);
      EXPECT_EQ(spot.name, "Bulb");
      EXPECT_NEAR(std::tan(glm::radians(spot.fovDeg) * 0.5f), tangent, 1e-5f);
      EXPECT_LT(glm::distance(spot.axis(), cubeForward(face)), 1e-6f) << cubeFaceName(face);
      EXPECT_EQ(glm::cross(cubeForward(face), cubeUp(face)), cubeRight(face));
      const glm::mat4 eye = lightEyeMatrix(spot, Bounds{});
      const glm::mat3 rotation(eye);  // rows of the look-at: right, up, -forward
      for (int c = 0; c < 3; ++c) {   // glm::normalize may leave 1 - 1 ulp
        EXPECT_NEAR(glm::row(rotation, 0)[c], cubeRight(face)[c], 1e-6f) << cubeFaceName(face);
        EXPECT_NEAR(glm::row(rotation, 1)[c], cubeUp(face)[c], 1e-6f) << cubeFaceName(face);
        EXPECT_NEAR(glm::row(rotation, 2)[c], -cubeForward(face)[c], 1e-6f) << cubeFaceName(face);
      }
    }
  }
}

class CubeKernels : public test::ClTest {};

using ref::positionsAround;

TEST_F(CubeKernels, ClassifyAgreesWithTheDefinitionOnTheDevice) {
  for (const glm::vec3 light : {glm::vec3(0.0f), glm::vec3(0.75f, -2.5f, 10.0f)}) {
    std::vector<glm::vec3> directions = adversarialDirections();
    for (const glm::vec3& v : randomDirections(5000, 3)) directions.push_back(v);
    GBuffer g;
    g.width = static_cast<int>(directions.size()), g.height = 1;
    const std::vector<cl_float4> position = positionsAround(light, directions);
    g.position = Buffer<cl_float4>(ctx(), std::span<const cl_float4>(position));
    Buffer<int32_t> faces;
    classifyCubeFaces(ctx(), g, light, faces);
    const std::vector<int32_t> device = faces.download(ctx()), expected = ref::cubeClassify(position, light);
    ASSERT_EQ(device.size(), expected.size());
    size_t covered = 0;
    for (size_t i = 0; i < device.size(); ++i) {
      ASSERT_EQ(device[i], expected[i]) << i << ": " << position[i].s[0] << " " << position[i].s[1] << " "
                                        << position[i].s[2];
      covered += device[i] != CUBE_NO_FACE;
      // The host's rule on the same float direction: host and device agree bit for bit.
      if (position[i].s[3] != 0.0f) {
        ASSERT_EQ(device[i],
                  cubeFaceOf({position[i].s[0] - light.x, position[i].s[1] - light.y, position[i].s[2] - light.z}));
      }
    }
    EXPECT_GT(covered, directions.size() * 3 / 4);
  }
}

TEST_F(CubeKernels, FaceGBufferAndCopyMatchTheirReferences) {
  // A 37x23 grid of points on a sphere around the light (odd sizes: no multiple of the work-group), a few background.
  const int width = 37, height = 23;
  const glm::vec3 light(0.5f, 1.0f, -2.0f);
  std::vector<cl_float4> position;
  std::vector<float> depth;
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) {
      const float theta = 3.14159f * (y + 0.5f) / height, phi = 6.28318f * (x + 0.5f) / width;
      const glm::vec3 q =
          light + 3.0f * glm::vec3(std::sin(theta) * std::cos(phi), std::cos(theta), std::sin(theta) * std::sin(phi));
      position.push_back({{q.x, q.y, q.z, (x * 7 + y) % 17 == 0 ? 0.0f : 1.0f}});
      depth.push_back(static_cast<float>(x + y));
    }
  GBuffer camera;
  camera.width = width, camera.height = height;
  camera.position = Buffer<cl_float4>(ctx(), std::span<const cl_float4>(position));
  camera.depth = Buffer<float>(ctx(), std::span<const float>(depth));
  Buffer<int32_t> faces;
  classifyCubeFaces(ctx(), camera, light, faces);
  const std::vector<int32_t> faceOf = faces.download(ctx());
  const float tangent = 1.3f;
  std::vector<float> start(position.size(), test::kPoison);
  Buffer<float> visibility(ctx(), std::span<const float>(start));
  for (int face = 0; face < CUBE_FACES; ++face) {
    GBuffer masked;
    maskCubeFace(ctx(), camera, faces, light, face, tangent, masked);
    const std::vector<cl_float4> p = masked.position.download(ctx());
    const std::vector<float> d = masked.depth.download(ctx());
    const std::vector<bool> kept = ref::cubeKept(position, faceOf, width, height, light, face, tangent);
    size_t own = 0, guard = 0;
    for (size_t i = 0; i < p.size(); ++i) {
      if (kept[i]) {
        ASSERT_EQ(std::memcmp(&p[i], &position[i], sizeof(cl_float4)), 0) << cubeFaceName(face) << " pixel " << i;
        ASSERT_EQ(d[i], depth[i]);
        (faceOf[i] == face ? own : guard)++;
      } else {
        ASSERT_EQ(p[i].s[3], 0.0f) << cubeFaceName(face) << " pixel " << i;
        ASSERT_EQ(d[i], kInf);
      }
    }
    EXPECT_GT(own, 20u) << cubeFaceName(face);
    EXPECT_GT(guard, 5u) << cubeFaceName(face) << ": neighbours across the face's edges";
    std::vector<float> faceVisibility(position.size(), static_cast<float>(face) + 0.5f);
    selectCubeFace(ctx(), faces, Buffer<float>(ctx(), std::span<const float>(faceVisibility)), face, visibility);
  }
  const std::vector<float> v = visibility.download(ctx());
  for (size_t i = 0; i < v.size(); ++i)
    ASSERT_EQ(v[i], faceOf[i] == CUBE_NO_FACE ? test::kPoison : static_cast<float>(faceOf[i]) + 0.5f) << i;
}

}  // namespace cube_test
}  // namespace penumbra
