// Technique parameters: defaults, validation of text values, choices, provenance text; and the registry.
#include "host/techniques/params.h"

#include <gtest/gtest.h>

#include "host/techniques/technique.h"

namespace penumbra {
namespace params_test {

std::vector<ParamSpec> specs() { return {{"radius", 2, 0, 16, "r"}, {"mode", 1, 0, 1, "m", {"uniform", "adaptive"}}}; }

TEST(Params, DefaultsAndValidatedValues) {
  Params params(specs());
  EXPECT_EQ(params.get("radius"), 2);
  EXPECT_EQ(params.describe(), "radius=2 mode=adaptive");
  params.set("radius", "3.5");
  params.set("mode", "uniform");
  EXPECT_EQ(params.get("radius"), 3.5);
  EXPECT_EQ(params.getInt("mode"), 0);
  EXPECT_THROW(params.set("radius", "17"), std::invalid_argument);
  EXPECT_THROW(params.set("radius", "-1"), std::invalid_argument);
  EXPECT_THROW(params.set("radius", "nan"), std::invalid_argument);
  EXPECT_THROW(params.set("radius", "2x"), std::invalid_argument);
  EXPECT_THROW(params.set("radius", ""), std::invalid_argument);
  EXPECT_THROW(params.set("mode", "other"), std::invalid_argument);
  EXPECT_THROW(params.set("nope", "1"), std::invalid_argument);
  EXPECT_THROW(params.get("nope"), std::out_of_range);
}

TEST(TechniqueRegistry, EveryTechniqueHasValidDefaults) {
  ASSERT_FALSE(techniques().empty());
  for (const TechniqueInfo& info : techniques()) {
    EXPECT_EQ(&findTechnique(info.name), &info);
    for (const ParamSpec& spec : info.params) {
      if (spec.isAuto(spec.defaultValue)) {  // chosen per frame (blur-radius auto): its value lies outside the range
        EXPECT_TRUE(spec.autoValue < spec.min || spec.autoValue > spec.max) << info.name << " --" << spec.name;
        continue;
      }
      EXPECT_GE(spec.defaultValue, spec.min) << info.name << " --" << spec.name;
      EXPECT_LE(spec.defaultValue, spec.max) << info.name << " --" << spec.name;
    }
    EXPECT_NE(info.create(Params(info.params)), nullptr);
  }
  EXPECT_THROW(findTechnique("nope"), std::invalid_argument);
}

}  // namespace params_test
}  // namespace penumbra
