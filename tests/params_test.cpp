// Technique parameters: defaults, validation of text values, choices, provenance text; and the registry.
#include "host/techniques/params.h"

#include <fmt/format.h>
#include <gtest/gtest.h>

#include <memory>
#include <set>
#include <string>

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
    EXPECT_NE(info.create(Params(info.params), 1024), nullptr);
  }
  EXPECT_THROW(findTechnique("nope"), std::invalid_argument);
}

// Another valid value of `spec` than its default: the next choice, or the far end of its range.
std::string otherValue(const ParamSpec& spec) {
  if (!spec.choices.empty()) return spec.choices[(static_cast<size_t>(spec.defaultValue) + 1) % spec.choices.size()];
  const double value = spec.isAuto(spec.defaultValue) || spec.defaultValue != spec.max ? spec.max : spec.min;
  return fmt::format("{}", value);
}

TEST(TechniqueRegistry, AnInstanceIsItsTypedSettings) {
  // The renderer keeps an instance while matches() holds, so every parameter the instance reads must change it; the
  // renderer's own (auto map size's range, the point light's cube guard) do not.
  const std::set<std::string> renderers = {"map-size-quantile",     "map-size-penumbra", "map-size-penumbra-quantile",
                                           "map-size-penumbra-max", "map-size-detail",   "map-size-min",
                                           "map-size-max",          "cube-guard"};
  for (const TechniqueInfo& info : techniques()) {
    const Params defaults(info.params);
    const std::unique_ptr<Technique> instance = info.create(defaults, 1024);
    EXPECT_TRUE(instance->matches(defaults, 1024)) << info.name;
    if (defaults.isAuto("map-size")) {
      EXPECT_FALSE(instance->matches(defaults, 2048)) << info.name << ": a new size";
    }
    int changed = 0;
    for (const ParamSpec& spec : info.params) {
      if (spec.text) continue;  // lvsm-splits needs a placement that takes it
      Params other = defaults;
      other.set(spec.name, otherValue(spec));
      try {
        info.create(other, 1024);
      } catch (const std::invalid_argument&) {
        continue;  // contradicts another default (jittered's rotation under its LiSPSM warp)
      }
      EXPECT_EQ(instance->matches(other, 1024), renderers.count(spec.name) != 0)
          << info.name << " --" << spec.name << " " << otherValue(spec);
      ++changed;
    }
    EXPECT_GT(changed, 0) << info.name;
  }
  // --map-size auto needs the frame's size: a technique made without one is a caller's error.
  const TechniqueInfo& sm = findTechnique("sm");
  EXPECT_THROW(sm.create(Params(sm.params), 0), std::logic_error);
}

TEST(TechniqueRegistry, ContradictingValuesAreRefusedWithBothOptionsNamed) {
  const auto refusal = [](const std::string& technique, const ParamValues& values) -> std::string {
    const TechniqueInfo& info = findTechnique(technique);
    try {
      info.create(techniqueParams(info, values), 1024);
    } catch (const std::invalid_argument& e) {
      return e.what();
    }
    return "accepted";
  };
  EXPECT_EQ(refusal("savsm", {{"savsm-width", "9"}, {"savsm-max-width", "8"}}),
            "--savsm-width 9 is larger than --savsm-max-width 8");
  EXPECT_EQ(refusal("lvsm", {{"lvsm-transition", "0.1"}, {"lvsm-overlap", "0.05"}}),
            "--lvsm-transition 0.1 is larger than --lvsm-overlap 0.05");
  EXPECT_EQ(refusal("pssm", {{"pssm-snap", "on"}, {"warp", "lispsm"}}),
            "--pssm-snap on cannot be combined with --warp lispsm");
  EXPECT_EQ(refusal("jittered", {{"lispsm-n-jitter", "1"}, {"warp", "none"}}), "--lispsm-n-jitter needs --warp lispsm");
  EXPECT_EQ(refusal("sm", {{"bias", "2"}}), "accepted");
}

}  // namespace params_test
}  // namespace penumbra
