// Bench's plain logic: medians and per-pass summaries over runs, bandwidth floors, sweep parsing and expansion,
// the CSV/JSON writer (columns, quoting, empty cells); on the device: the copy bandwidth measurement, the byte hints
// the profiler collects, Renderer reuse across frames, and the lit.Y mask and its effect on compareImages().
#include <gtest/gtest.h>

#include <map>
#include <set>

#include <cmath>
#include <sstream>
#include <stdexcept>

#include "tools/eval/bandwidth.h"
#include "tools/eval/bench_report.h"
#include "tools/eval/bench_stats.h"
#include "host/eval/metrics.h"
#include "tools/eval/sweep.h"
#include "host/pipeline/frame_image.h"
#include "host/pipeline/renderer.h"
#include "host/scene/framing.h"
#include "host/scene/procedural.h"
#include "host/techniques/registry.h"
#include "tests/support/cl_test.h"

namespace penumbra {
namespace bench_test {

TEST(BenchStats, MedianOfOddEvenAndEmpty) {
  EXPECT_DOUBLE_EQ(median({3, 1, 2}), 2.0);
  EXPECT_DOUBLE_EQ(median({4, 1, 3, 2}), 2.5);
  EXPECT_DOUBLE_EQ(median({7}), 7.0);
  EXPECT_DOUBLE_EQ(median({}), 0.0);
  EXPECT_DOUBLE_EQ(median({5, 5, 100, 5}), 5.0);  // an outlier run does not move it
}

TEST(BenchStats, BandwidthFloorIsBytesOverBandwidth) {
  EXPECT_DOUBLE_EQ(*bandwidthFloorMs(1'000'000'000, 10e9), 100.0);  // 1 GB at 10 GB/s
  EXPECT_DOUBLE_EQ(*bandwidthFloorMs(4096, 4096e3), 1.0);
  EXPECT_FALSE(bandwidthFloorMs(0, 10e9));  // no byte hint: no floor
  EXPECT_FALSE(bandwidthFloorMs(100, 0));   // bandwidth unknown
}

TEST(BenchStats, SummariseTakesPerPassMediansAndTheMedianTotal) {
  const std::vector<std::vector<PassTime>> runs = {
      {{"raster/fine_raster", 2.0, 1, 800}, {"shade/pcf_visibility", 10.0, 1, 3600}},
      {{"raster/fine_raster", 4.0, 1, 800}, {"shade/pcf_visibility", 1.0, 1, 3600}},
      {{"raster/fine_raster", 3.0, 1, 800}, {"shade/pcf_visibility", 2.0, 1, 3600}, {"transfer/fill", 1.0, 2, 64}},
  };
  const RunSummary s = summariseRuns(runs);
  ASSERT_EQ(s.passes.size(), 3u);
  EXPECT_EQ(s.passes[0].name, "raster/fine_raster");
  EXPECT_DOUBLE_EQ(s.passes[0].ms, 3.0);
  EXPECT_DOUBLE_EQ(s.passes[1].ms, 2.0);
  EXPECT_DOUBLE_EQ(s.passes[2].ms, 0.0);  // absent in two of three runs: median 0
  EXPECT_EQ(s.passes[2].calls, 2);
  EXPECT_EQ(s.totalBytes, 800u + 3600u + 64u);
  EXPECT_DOUBLE_EQ(s.totalMs, 6.0);  // run totals 12, 5, 6: median 6 (not the sum of the pass medians, 5)
}

TEST(Sweep, ParsesNameAndValues) {
  const Sweep s = parseSweep("map-size=512,1024,2048");
  EXPECT_EQ(s.param, "map-size");
  EXPECT_EQ(s.values, (std::vector<std::string>{"512", "1024", "2048"}));
  EXPECT_EQ(parseSweep("--blur-radius=3").param, "blur-radius");
  EXPECT_EQ(parseSweep("bias=0.5").values.size(), 1u);
  for (const char* bad : {"map-size", "=1,2", "map-size=", "map-size=1,,2", "map-size=1,"})
    EXPECT_THROW(parseSweep(bad), std::invalid_argument) << bad;
}

TEST(Sweep, ExpandsOnlyTheParametersATechniqueHas) {
  const TechniqueInfo pcf = pcfTechnique(), sm = smTechnique();
  const std::vector<Sweep> sweeps = {parseSweep("map-size=512,1024"), parseSweep("pcf-radius=1,2,3")};
  std::vector<std::string> skipped;
  const std::vector<Setting> a = expandSweeps(pcf, sweeps, &skipped);
  ASSERT_EQ(a.size(), 6u);
  EXPECT_TRUE(skipped.empty());
  EXPECT_EQ(a.front().label, "map-size=512 pcf-radius=1");  // the first sweep varies slowest
  EXPECT_EQ(a.back().label, "map-size=1024 pcf-radius=3");
  const std::vector<Setting> b = expandSweeps(sm, sweeps, &skipped);
  EXPECT_EQ(b.size(), 2u);
  EXPECT_EQ(skipped, std::vector<std::string>{"pcf-radius"});
  EXPECT_EQ(expandSweeps(sm, {}).front().label, "default");
  EXPECT_THROW(checkSweeps({parseSweep("pcf-radius=1")}, {&sm}), std::invalid_argument);
  EXPECT_THROW(checkSweeps({parseSweep("bias=1"), parseSweep("bias=2")}, {&sm}), std::invalid_argument);
  EXPECT_NO_THROW(checkSweeps(sweeps, {&sm, &pcf}));
}

// "default" holds the parameter at the technique's own default: auto for pcf's map size, 2048 for jittered's.
TEST(Sweep, DefaultHoldsTheTechniquesOwnValue) {
  const Sweep sizes = parseSweep("map-size=default,512");
  for (const char* name : {"pcf", "jittered"}) {
    const std::vector<Setting> s = expandSweeps(findTechnique(name), {sizes});
    ASSERT_EQ(s.size(), 2u) << name;
    EXPECT_EQ(s[0].label, "map-size=default") << name;
    EXPECT_TRUE(s[0].values.empty()) << name;
    EXPECT_EQ(s[0].defaults, std::set<std::string>{"map-size"}) << name;
    EXPECT_EQ(s[1].values.at("map-size"), "512") << name;
    EXPECT_TRUE(s[1].defaults.empty()) << name;
  }
  const std::vector<Setting> zipped = expandSweeps(findTechnique("pcf"), {parseSweep("pcf-radius+map-size=2+default")});
  ASSERT_EQ(zipped.size(), 1u);
  EXPECT_EQ(zipped[0].values, (std::map<std::string, std::string>{{"pcf-radius", "2"}}));
  EXPECT_EQ(zipped[0].defaults, std::set<std::string>{"map-size"});
}

TEST(Sweep, MovesSeveralParametersTogether) {
  const Sweep zipped = parseSweep("pcf-radius+map-size=1+2048,4+1024");
  EXPECT_EQ(zipped.param, "pcf-radius+map-size");
  ASSERT_EQ(zipped.names.size(), 2u);
  const TechniqueInfo &pcf = findTechnique("pcf"), &sm = findTechnique("sm");
  std::vector<std::string> skipped;
  const std::vector<Setting> a = expandSweeps(pcf, {zipped}, &skipped);
  ASSERT_EQ(a.size(), 2u) << "zipped, not a product";
  EXPECT_EQ(a[1].values.at("pcf-radius"), "4");
  EXPECT_EQ(a[1].values.at("map-size"), "1024");
  EXPECT_EQ(a[1].label, "pcf-radius+map-size=4+1024");
  EXPECT_EQ(expandSweeps(sm, {zipped}, &skipped).front().label, "default") << "sm lacks pcf-radius";
  EXPECT_EQ(skipped.back(), "pcf-radius+map-size");
  for (const char* bad : {"a+b=1", "a+b=1+2+3", "a+=1+2", "a+b=1+,2+3"})
    EXPECT_THROW(parseSweep(bad), std::invalid_argument) << bad;
  EXPECT_THROW(checkSweeps({zipped, parseSweep("map-size=512")}, {&pcf}), std::invalid_argument);
}

std::vector<BenchRow> exampleRows() {
  BenchRow pass{"builtin:box",
                "pcf",
                "map-size=512",
                "bias=1, \"x\"",
                "shade/pcf_visibility",
                1,
                2.5,
                3600,
                0.25,
                {},
                "",
                {},
                {}};
  pass.light = "Key";
  BenchRow total = pass;
  total.pass = kTotalPass;
  total.bytes = 0;
  total.floorMs.reset();
  ErrorMetrics m;
  m.pixels = 10, m.mae = 0.125, m.leak = 0.5, m.penumbraMae = 0.25, m.penumbraPixels = 4;
  total.metrics = m;
  total.wallMs = 12.5, total.firstWallMs = 480;
  return {pass, total};
}

std::vector<std::string> splitLines(const std::string& text) {
  std::vector<std::string> lines;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);) lines.push_back(line);
  return lines;
}

TEST(BenchReport, CsvHasTheColumnsAndQuotesFields) {
  EXPECT_EQ(csvField("plain"), "plain");
  EXPECT_EQ(csvField("a,b"), "\"a,b\"");
  EXPECT_EQ(csvField("say \"hi\""), "\"say \"\"hi\"\"\"");
  std::ostringstream out;
  BenchMeta meta{"Device, v1", 2e9, 64, 32, 3, 1, "", false};
  writeBenchCsv(out, meta, exampleRows());
  const std::vector<std::string> lines = splitLines(out.str());
  ASSERT_EQ(lines.size(), 3u);
  EXPECT_EQ(lines[0],
            "scene,technique,setting,pass,calls,ms,bytes,floor_ms,mae,rmse,p95,max,off,leak,false_shadow,umbra_light,"
            "mean_signed,pixels,width,height,runs,copy_gbps,device,parameters,light,penumbra_mae,penumbra_pixels,"
            "bytes_per_pixel,wall_ms,first_wall_ms");
  EXPECT_EQ(lines[1],
            "builtin:box,pcf,map-size=512,shade/pcf_visibility,1,2.5,3600,0.25,,,,,,,,,,,64,32,3,2,"
            "\"Device, v1\",\"bias=1, \"\"x\"\"\",Key,,,1.7578125,,");  // 3600 bytes over 64 x 32 pixels
  EXPECT_EQ(lines[2],
            "builtin:box,pcf,map-size=512,total,1,2.5,,,0.125,0,0,0,0,0.5,0,0,0,10,64,32,3,2,"
            "\"Device, v1\",\"bias=1, \"\"x\"\"\",Key,0.25,4,,12.5,480");
}

TEST(BenchReport, JsonCarriesMetaAndTheSameRows) {
  BenchMeta meta{"dev", 5e9, 64, 32, 3, 1, "ref.exr", true};
  const nlohmann::json j = benchJson(meta, exampleRows());
  EXPECT_EQ(j["meta"]["device"], "dev");
  EXPECT_DOUBLE_EQ(j["meta"]["copy_bandwidth_gbps"].get<double>(), 5.0);
  EXPECT_EQ(j["meta"]["masked"], true);
  ASSERT_EQ(j["rows"].size(), 2u);
  EXPECT_TRUE(j["rows"][0]["mae"].is_null());
  EXPECT_EQ(j["rows"][0]["bytes"], 3600);
  EXPECT_TRUE(j["rows"][1]["floor_ms"].is_null());
  EXPECT_DOUBLE_EQ(j["rows"][1]["mae"].get<double>(), 0.125);
  EXPECT_DOUBLE_EQ(j["rows"][1]["first_wall_ms"].get<double>(), 480.0);
  EXPECT_TRUE(j["rows"][0]["wall_ms"].is_null());  // pass rows have no wall time
  EXPECT_EQ(j["rows"][1].size(), benchCsvColumns().size());
}

class BenchDevice : public test::ClTest {};

TEST_F(BenchDevice, CopyBandwidthIsMeasuredAndPositive) {
  const CopyBandwidth b = measureCopyBandwidth(ctx(), size_t{16} << 20, 3);
  EXPECT_EQ(b.bufferBytes, size_t{16} << 20);
  EXPECT_GT(b.medianMs, 0.0);
  EXPECT_NEAR(b.bytesPerSecond, 2.0 * b.bufferBytes / (b.medianMs * 1e-3), b.bytesPerSecond * 1e-9);
}

TEST_F(BenchDevice, PassesCarryByteHintsAndTheRendererKeepsItsTechnique) {
  const Scene scene = makeProcedural("box");
  Camera camera = scene.cameras.empty() ? framingCamera(scene.bounds()) : scene.cameras.front();
  camera.width = 61, camera.height = 37;
  const Light light = scene.lights.empty() ? framingLight(scene.bounds()) : scene.lights.front();
  const TechniqueInfo& sm = findTechnique("sm");
  Params params(sm.params);
  params.set("map-size", "128");
  Renderer renderer(ctx(), scene);
  const RenderResult first = renderer.render(camera, light, sm, params);
  const RenderResult second = renderer.render(camera, light, sm, params);
  EXPECT_EQ(first.image.require("visibility.Y").data, second.image.require("visibility.Y").data);
  auto bytesOf = [&](const RenderResult& r, const std::string& name) {
    for (const PassTime& p : r.passes)
      if (p.name == name) return p.bytes;
    ADD_FAILURE() << name << " not profiled";
    return uint64_t{0};
  };
  const uint64_t pixels = 61 * 37;
  EXPECT_EQ(bytesOf(second, "shade/sm_visibility"), pixels * 36);  // position + normal in, visibility out
  EXPECT_EQ(bytesOf(second, "shade/shade_preview"), pixels * 52);
  EXPECT_GT(bytesOf(second, "raster/fine_raster"), 0u);
  EXPECT_GT(bytesOf(second, "transfer/fill"), 0u);
}

TEST(LitMask, FacingAndConeFollowThePreview) {
  Camera camera;
  camera.eye = {0, 5, 5};
  Light spot;  // at (0,10,0) aiming down, 60 degree cone
  const std::vector<cl_float4> position = {{{0, 0, 0, 1}}, {{0, 0, 0, 1}}, {{50, 0, 0, 1}}, {{0, 0, 0, 0}}};
  const std::vector<cl_float4> normal = {{{0, 1, 0, 0}}, {{0, -1, 0, 0}}, {{0, 1, 0, 0}}, {{0, 1, 0, 0}}};
  // Up-facing under the light: lit. Down-facing: turned towards the camera (above), so lit too. Far outside the
  // cone: not. Background: not.
  EXPECT_EQ(litMask(position, normal, camera, spot), (std::vector<float>{1, 1, 0, 0}));
  camera.eye = {0, -5, 5};  // the camera below the floor sees its underside: faces away from the light
  EXPECT_EQ(litMask(position, normal, camera, spot), (std::vector<float>{0, 0, 0, 0}));
  Light sun;
  sun.type = LightType::Directional;
  sun.direction = {0, -1, 0};
  camera.eye = {0, 5, 5};
  EXPECT_EQ(litMask(position, normal, camera, sun), (std::vector<float>{1, 1, 1, 0}));  // no cone
}

TEST(LitMask, CompareCountsCoveredPixelsInsideTheMask) {
  Image ours(4, 1), ref(4, 1);
  ours.add("visibility.Y", {1, 1, 0, 1});
  ref.add("visibility.Y", {1, 0, 0, 0});
  ref.add("A", {1, 1, 1, 0});
  ref.add(kLitChannel, {1, 0, 1, 1});
  const ErrorMetrics masked = compareImages(ours, ref);
  EXPECT_EQ(masked.pixels, 2u);  // pixels 0 and 2: covered and lit
  EXPECT_DOUBLE_EQ(masked.leak, 0.0);
  CompareSpec noMask;
  noMask.mask.clear();
  const ErrorMetrics all = compareImages(ours, ref, noMask);
  EXPECT_EQ(all.pixels, 3u);
  EXPECT_DOUBLE_EQ(all.leak, 1.0 / 3);  // pixel 1 faces away: its "leak" never shows
  EXPECT_TRUE(hasMask(ours, ref, CompareSpec{}));
  EXPECT_FALSE(hasMask(ours, ref, noMask));
}

}  // namespace bench_test
}  // namespace penumbra
