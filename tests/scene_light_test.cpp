// Light: the command-line forms of spot, directional and point lights (good and bad), the axis, describe()
// giving back a form that parses to the same light, and the refusal of point lights.
#include <stdexcept>

#include <gtest/gtest.h>

#include "host/scene/light.h"
#include "scene_test_util.h"

namespace penumbra {
namespace scene_light_test {

using test::throwsWith;

TEST(LightParse, Spot) {
  const Light l = parseLight("spot:0,10,0:0,0,0:60");
  EXPECT_EQ(l.type, LightType::Spot);
  EXPECT_EQ(l.position, glm::vec3(0, 10, 0));
  EXPECT_EQ(l.fovDeg, 60.0f);
  EXPECT_EQ(l.radius, 0.0f);
  EXPECT_FALSE(l.isArea());
  EXPECT_EQ(l.axis(), glm::vec3(0, -1, 0));
}

TEST(LightParse, SpotDisk) {
  const Light l = parseLight("spot:1,2,3:4,5,6:45:0.25");
  EXPECT_EQ(l.radius, 0.25f);
  EXPECT_TRUE(l.isArea());
}

TEST(LightParse, DirectionalIsNormalised) {
  const Light l = parseLight("dir:0,-3,4:0.5");
  EXPECT_EQ(l.type, LightType::Directional);
  EXPECT_NEAR(glm::length(l.direction), 1.0f, 1e-6f);
  EXPECT_NEAR(l.direction.y, -0.6f, 1e-6f);
  EXPECT_EQ(l.angularRadiusDeg, 0.5f);
  EXPECT_TRUE(l.isArea());
  EXPECT_FALSE(parseLight("dir:0,-1,0").isArea());
}

struct BadLight {
  const char* spec;
  const char* part;
};

class LightParseBad : public ::testing::TestWithParam<BadLight> {};

TEST_P(LightParseBad, NamesTheBadPart) {
  EXPECT_TRUE(throwsWith<std::invalid_argument>([&] { parseLight(GetParam().spec); }, {GetParam().part}));
}

INSTANTIATE_TEST_SUITE_P(
    Light, LightParseBad,
    ::testing::Values(BadLight{"", "unknown light type"}, BadLight{"area:0,0,0", "unknown light type"},
                      BadLight{"point:0,0", "position"}, BadLight{"point:0,0,0:-1", "radius"},
                      BadLight{"point:0,0,0:1:2", "expected point"}, BadLight{"point:nan,0,0", "position"},
                      BadLight{"spot:0,1,0:0,0,0", "expected spot"},
                      BadLight{"spot:0,1,0:0,0,0:60:1:2", "expected spot"}, BadLight{"spot:0,1:0,0,0:60", "position"},
                      BadLight{"spot:0,1,0:0,0,q:60", "target z"},
                      BadLight{"spot:1,1,1:1,1,1:60", "position equals target"}, BadLight{"spot:0,1,0:0,0,0:0", "fov"},
                      BadLight{"spot:0,1,0:0,0,0:180", "fov"}, BadLight{"spot:0,1,0:0,0,0:nan", "fov"},
                      BadLight{"spot:0,1,0:0,0,0:60:-1", "radius"}, BadLight{"spot:0,1,0:0,0,0:60:inf", "radius"},
                      BadLight{"dir:0,0,0", "direction: zero"}, BadLight{"dir:0,-1,0:45", "angular radius"},
                      BadLight{"dir:0,-1,0:-0.1", "angular radius"}, BadLight{"dir:0,-1,0:1:2", "expected dir"},
                      BadLight{"dir:0,-1,0,", "direction"}, BadLight{"dir:1e30,1e30,1e30", "direction"},
                      BadLight{"spot:0,1,0:0,0,0:60:", "radius"}));

TEST(LightParse, Point) {
  const Light l = parseLight("point:1,2,3:0.5");
  EXPECT_EQ(l.type, LightType::Point);
  EXPECT_EQ(l.position, glm::vec3(1, 2, 3));
  EXPECT_EQ(l.radius, 0.5f);
  EXPECT_TRUE(l.isArea());
  EXPECT_FALSE(parseLight("point:1,2,3").isArea());
  EXPECT_EQ(l.label(), "point:1,2,3:0.5");
}

TEST(LightDescribe, RoundTrips) {
  for (const char* spec : {"spot:0,10,0:0,0,0:60", "spot:1.5,2,-3:0.1,0.2,0.3:33:0.125", "dir:0,-1,0",
                           "dir:0.6,-0.8,0:0.25", "point:1,2,3", "point:-1,0.5,2:0.25"}) {
    const Light l = parseLight(spec);
    const Light m = parseLight(l.describe());
    EXPECT_EQ(l.describe(), m.describe()) << spec;
    EXPECT_EQ(l.position, m.position);
    EXPECT_EQ(l.target, m.target);
    EXPECT_EQ(l.direction, m.direction);
    EXPECT_EQ(l.fovDeg, m.fovDeg);
    EXPECT_EQ(l.radius, m.radius);
    EXPECT_EQ(l.angularRadiusDeg, m.angularRadiusDeg);
  }
  EXPECT_EQ(parseLight("spot:0,10,0:0,0,0:60:0.5").describe(), "spot:0,10,0:0,0,0:60:0.5");
}

}  // namespace scene_light_test
}  // namespace penumbra
