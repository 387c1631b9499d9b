// `penumbra selftest`'s driver (tools/selftest/selftest.h): a check that passes, fails, does not apply, fails to build
// or throws becomes one row and never stops the run; the lists, the filter and the JSON rows. Whether every check
// passes on this device is the `selftest` ctest entry's question (the tool itself).
#include "tools/selftest/selftest.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <nlohmann/json.hpp>
#include <set>
#include <stdexcept>

#include "host/cl/buffer.h"
#include "host/cl/error.h"
#include "host/cl/profiler.h"
#include "tests/support/cl_test.h"

namespace penumbra {
namespace selftest_test {

using selftest::Check;
using selftest::Measured;
using selftest::Row;

class Selftest : public test::ClTest {};

Measured comparing(std::vector<float> actual, std::vector<double> expected) {
  return {ref::compare(std::span<const float>(actual), std::span<const double>(expected), {1e-3, 0.0}), "units"};
}

TEST_F(Selftest, EveryOutcomeIsARow) {
  const Row pass = selftest::run(ctx(), {"stage", "pass", true, [](Context&) { return comparing({1.0f}, {1.0005}); }});
  EXPECT_EQ(pass.status, "pass");
  EXPECT_EQ(pass.count, 1u);
  EXPECT_NEAR(pass.error, 5e-4, 1e-7);
  EXPECT_EQ(pass.tolerance, 1e-3);
  EXPECT_EQ(pass.unit, "units");
  EXPECT_TRUE(pass.message.empty());

  const Row fail = selftest::run(ctx(), {"stage", "fail", true, [](Context&) {
                                           return comparing({1.0f, NAN}, {1.1, 2.0});
                                         }});
  EXPECT_EQ(fail.status, "fail");
  EXPECT_EQ(fail.mismatches, 2u);
  EXPECT_TRUE(std::isinf(fail.error)) << "a NaN where the reference has a number is the worst error";
  EXPECT_NE(fail.message.find("[0]: 1 vs expected 1.1"), std::string::npos) << fail.message;

  const Row skipped = selftest::run(ctx(), {"stage", "skip", true, [](Context&) -> Measured {
                                              throw selftest::NotApplicable("fp64 tables need cl_khr_fp64");
                                            }});
  EXPECT_EQ(skipped.status, "skipped");
  EXPECT_EQ(skipped.message, "fp64 tables need cl_khr_fp64");

  const Row build = selftest::run(ctx(), {"stage", "build", true, [](Context&) -> Measured {
                                            throw BuildError("kernels/x.cl", "device", "-DX", "x.cl:3: error: nope");
                                          }});
  EXPECT_EQ(build.status, "error");
  EXPECT_EQ(build.buildLog, "x.cl:3: error: nope");

  const Row launch = selftest::run(ctx(), {"stage", "launch", true, [](Context&) -> Measured {
                                             throw ClError(CL_OUT_OF_RESOURCES, "clEnqueueNDRangeKernel", "k", "sat");
                                           }});
  EXPECT_EQ(launch.status, "error");
  EXPECT_NE(launch.message.find("CL_OUT_OF_RESOURCES"), std::string::npos) << launch.message;

  const Row thrown = selftest::run(
      ctx(), {"stage", "thrown", true, [](Context&) -> Measured { throw std::runtime_error("host trouble"); }});
  EXPECT_EQ(thrown.status, "error");
  EXPECT_EQ(thrown.message, "host trouble");
}

// Also the launches a step times with a profiler of its own (the Renderer does): ProfilerScopes nest.
TEST_F(Selftest, DeviceTimeCountsTheChecksLaunchesAlsoUnderAnInnerProfiler) {
  const Row row = selftest::run(ctx(), {"stage", "fill", true, [](Context& c) {
                                          Buffer<float> b(c, 1 << 20);
                                          Profiler inner;
                                          {
                                            ProfilerScope scope(c, inner);
                                            b.fill(c, 1.0f);
                                          }
                                          EXPECT_EQ(inner.resolve().size(), 1u);
                                          return comparing({1.0f}, {1.0});
                                        }});
  EXPECT_EQ(row.status, "pass");
  EXPECT_GT(row.deviceMs, 0.0) << "the fill under the inner scope reaches the selftest's profiler";
  EXPECT_EQ(ctx().profiler(), nullptr) << "the outer scope is gone, and with it the profiler";
}

TEST(SelftestList, QuickIsPartOfFullAndEveryStageIsThere) {
  const std::vector<Check> quick = selftest::checks(selftest::Depth::Quick),
                           full = selftest::checks(selftest::Depth::Full);
  std::set<std::string> fullIds, stages, quickStages;
  for (const Check& c : full) {
    EXPECT_TRUE(fullIds.insert(c.stage + "/" + c.name).second) << "duplicate " << c.stage << "/" << c.name;
    stages.insert(c.stage);
  }
  for (const Check& c : quick) {
    EXPECT_TRUE(c.quick);
    EXPECT_TRUE(fullIds.count(c.stage + "/" + c.name)) << c.name;
    quickStages.insert(c.stage);
  }
  const std::set<std::string> expected = {"moments", "blur", "sat",       "pyramid", "reduce",
                                          "raster",  "vssm", "technique", "caller"};
  EXPECT_EQ(stages, expected);
  EXPECT_EQ(quickStages, expected) << "--quick covers every stage";
  EXPECT_LT(quick.size(), full.size());
}

TEST(SelftestList, FilterTakesAnyOfItsCommaSeparatedTexts) {
  const std::vector<Check> some = selftest::checks(selftest::Depth::Full, "sat/Fixed64,raster/cube");
  ASSERT_FALSE(some.empty());
  for (const Check& c : some) {
    const std::string id = c.stage + "/" + c.name;
    EXPECT_TRUE(id.find("sat/Fixed64") != std::string::npos || id.find("raster/cube") != std::string::npos) << id;
  }
  EXPECT_TRUE(selftest::checks(selftest::Depth::Full, "no-such-check").empty());
  EXPECT_EQ(selftest::checks(selftest::Depth::Full, ",").size(), selftest::checks(selftest::Depth::Full).size());
}

TEST(SelftestJson, RowsAndInfiniteErrors) {
  Row row;
  row.stage = "sat", row.name = "x", row.status = "fail", row.error = INFINITY, row.tolerance = 1.0;
  row.buildLog = "log";
  const nlohmann::json j = selftest::toJson(row);
  EXPECT_TRUE(j["max_error"].is_null()) << "JSON has no infinity";
  EXPECT_EQ(j["tolerance"], 1.0);
  EXPECT_EQ(j["case"], "x");
  EXPECT_EQ(j["build_log"], "log");
  EXPECT_FALSE(j.contains("message"));
}

TEST_F(Selftest, DeviceReportNamesTheLayoutsChosen) {
  const nlohmann::json d = selftest::deviceReport(ctx());
  for (const char* key : {"platform", "name", "driver_version", "opencl_c_version", "extensions_used",
                          "local_mem_bytes", "work_group_layouts", "overrides"})
    EXPECT_TRUE(d.contains(key)) << key;
  for (const char* key : {"table", "raster", "blur", "sat", "pyramid"})
    EXPECT_TRUE(d["work_group_layouts"].contains(key)) << key;
}

}  // namespace selftest_test
}  // namespace penumbra
