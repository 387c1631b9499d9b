// The frame memory plan (host/pipeline/memory_plan.h): sizes from the image and the techniques' parameters, the
// refusal against a device's limits and --memory-limit, the size parser, and the frame checks (frame_check.h).
#include "host/pipeline/memory_plan.h"

#include <gtest/gtest.h>

#include "host/pipeline/frame_check.h"
#include "host/pipeline/map_size.h"
#include "host/scene/procedural.h"
#include "host/techniques/technique.h"
#include "kernels/shared/izb.h"

namespace penumbra {
namespace memory_plan_test {

constexpr uint64_t kGiB = uint64_t{1} << 30;

DeviceInfo deviceWith(uint64_t global, uint64_t maxAlloc) {
  DeviceInfo d;
  d.globalMemBytes = global, d.maxAllocBytes = maxAlloc;
  return d;
}

Camera cameraOf(int width, int height) {
  Camera c;
  c.width = width, c.height = height;
  return c;
}

TEST(MemoryPlan, TrilinearEvsm4At4096IsRefusedOnOneGiB) {
  const TechniqueInfo& evsm4 = findTechnique("evsm4");
  Params params(evsm4.params);
  params.set("moment-filtering", "trilinear");
  const MemoryPlan plan = planFrame(cameraOf(4096, 4096), {{LightType::Spot, &evsm4, &params}});
  EXPECT_GT(plan.deviceBytes(), kGiB);
  try {
    checkMemoryPlan(plan, deviceWith(kGiB, kGiB / 4), std::nullopt);
    FAIL() << "not refused";
  } catch (const MemoryError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("more than 1.0 GiB (the device's global memory)"), std::string::npos) << what;
    EXPECT_NE(what.find("G-buffer"), std::string::npos) << what;
  }
  EXPECT_NO_THROW(checkMemoryPlan(plan, deviceWith(16 * kGiB, 4 * kGiB), std::nullopt));
  EXPECT_THROW(checkMemoryPlan(plan, deviceWith(16 * kGiB, 4 * kGiB), kGiB), MemoryError);  // --memory-limit
}

TEST(MemoryPlan, GrowsWithPixelsLightsAndMaps) {
  const TechniqueInfo& sm = findTechnique("sm");
  Params small(sm.params), big(sm.params);
  big.set("map-size", "8192");
  const auto device = [](const Camera& c, const std::vector<PlannedLight>& l) { return planFrame(c, l).deviceBytes(); };
  EXPECT_LT(device(cameraOf(64, 64), {{LightType::Spot, &sm, &small}}),
            device(cameraOf(128, 64), {{LightType::Spot, &sm, &small}}));
  EXPECT_LT(device(cameraOf(64, 64), {{LightType::Spot, &sm, &small}}),
            device(cameraOf(64, 64), {{LightType::Spot, &sm, &big}}));
  EXPECT_LT(device(cameraOf(64, 64), {{LightType::Spot, &sm, &small}}),
            device(cameraOf(64, 64), {{LightType::Point, &sm, &small}}));  // six cube faces
  EXPECT_EQ(planFrame(cameraOf(8192, 8192), {{LightType::Spot, &sm, &small}}).hostBytes() / (8192ull * 8192),
            (4 + 7 + 4 + 1 + 1) * 4 + 4);  // the image's channels (preview, surfaces, debug, visibility) and PNG
  // A frame of the visibility alone (bench's): visibility.Y and the light's layer, no preview pass on the device.
  const MemoryPlan whole = planFrame(cameraOf(8192, 8192), {{LightType::Spot, &sm, &small}});
  const MemoryPlan bare = planFrame(cameraOf(8192, 8192), {{LightType::Spot, &sm, &small}}, FrameDownload::Image, {},
                                    FrameOutputs::visibilityOnly());
  EXPECT_EQ(bare.hostBytes() / (8192ull * 8192), 2u * 4);
  EXPECT_EQ(whole.deviceBytes() - bare.deviceBytes(), 8192ull * 8192 * 16);  // the preview's float4
  // A deferred frame (penumbra render) holds its writers' bands on the host, not the image.
  EXPECT_EQ(planFrame(cameraOf(8192, 8192), {{LightType::Spot, &sm, &small}}, FrameDownload::Deferred).hostBytes(),
            kDeferredHostBytes);
  // --map-size auto is planned at the largest size it may choose, with its drawn probe (depth and ids).
  Params automatic(sm.params), largest(sm.params);
  automatic.set("map-size", "auto");
  largest.set("map-size", std::to_string(largest.getInt("map-size-max")));
  EXPECT_EQ(device(cameraOf(64, 64), {{LightType::Spot, &sm, &automatic}}),
            device(cameraOf(64, 64), {{LightType::Spot, &sm, &largest}}) + uint64_t{kMapProbeSize} * kMapProbeSize * 8);
}

// izb at 4K with 32 samples a pixel: its passes of at most --izb-chunk samples bound the sample buffers (8 bytes a
// sample: 128 MiB at the default 2^24), far below the 265 M samples' 2 GiB; its grid is 24 bytes a cell (16 of the
// samples, 8 of an area light's caster lists) and 8 a tile of IZB_TILE_CELLS^2 cells (the clusters' tile lists), not
// a map, beside the light pattern's bitmask tables (256 KiB at the default 64 points).
TEST(MemoryPlan, IzbSamplesAreBoundedByItsChunk) {
  const TechniqueInfo& izb = findTechnique("izb");
  Params one(izb.params), many(izb.params), small(izb.params);
  many.set("izb-samples", "32");
  small.set("izb-samples", "32");
  small.set("izb-chunk", "65536");
  const Camera uhd = cameraOf(3840, 2160);
  const auto stage = [&](const Params& p, uint64_t triangles = 0) {
    const MemoryPlan plan = planFrame(uhd, {{LightType::Spot, &izb, &p}}, FrameDownload::Image, {triangles, 0});
    for (const MemoryStage& s : plan.stages)
      if (s.name.find("grid and samples") != std::string::npos) return s.deviceBytes;
    ADD_FAILURE() << "no izb stage in " << plan.describe();
    return uint64_t{0};
  };
  const uint64_t tilesPerSide = (256 + IZB_TILE_CELLS - 1) / IZB_TILE_CELLS;
  const uint64_t cells = 256 * 256 * 24 + tilesPerSide * tilesPerSide * 8 + 256 * 64 * 2 * 4 * 2;
  EXPECT_EQ(stage(one), cells + 3840ull * 2160 * 8);  // one sample a pixel: below the chunk
  EXPECT_EQ(stage(many), cells + (uint64_t{1} << 24) * 8);
  EXPECT_EQ(stage(small), cells + 65536ull * 8);
  EXPECT_LT(planFrame(uhd, {{LightType::Spot, &izb, &many}}).deviceBytes(), kGiB);
  // Per triangle 64 bytes of caster record and 4 of its slot's triangle, and 48 per cluster of IZB_CLUSTER (its ball
  // and its box: izb_soft_casters, izb_soft_clusters, izb_soft_tiles): 1 M triangles of builtin:poles at its largest
  // add 71 MiB; a count that fills no whole cluster is padded to one.
  const uint64_t million = 1000000;
  EXPECT_EQ(stage(one, million) - stage(one), million * 68 + million / IZB_CLUSTER * 48);
  EXPECT_EQ(stage(one, million + 1) - stage(one), (million + IZB_CLUSTER) * 68 + (million / IZB_CLUSTER + 1) * 48);
}

// fvsm's atlas is planned at its texel budget (8 bytes a texel: depth and ids), or at the whole virtual map or a tile
// per pixel when either is smaller.
TEST(MemoryPlan, FvsmAtlasIsPlannedAtItsBudget) {
  const TechniqueInfo& fvsm = findTechnique("fvsm");
  Params params(fvsm.params), small(fvsm.params);
  small.set("fvsm-max-size", "1024");
  const auto maps = [&](const Params& p, int side) {
    for (const MemoryStage& s : planFrame(cameraOf(side, side), {{LightType::Spot, &fvsm, &p}}).stages)
      if (s.name.find("maps") != std::string::npos) return s.deviceBytes;
    return uint64_t{0};
  };
  EXPECT_EQ(maps(params, 64), static_cast<uint64_t>(params.get("fvsm-budget")) * 8);
  EXPECT_EQ(maps(small, 64), uint64_t{1024} * 1024 * 8);
  EXPECT_EQ(maps(params, 2), uint64_t{4} * 1024 * 1024 * 8);  // four pixels: four tiles at most
}

TEST(MemoryPlan, SingleBufferAboveTheDeviceMaximumIsNamed) {
  const TechniqueInfo& sm = findTechnique("sm");
  Params params(sm.params);
  const MemoryPlan plan = planFrame(cameraOf(8192, 8192), {{LightType::Spot, &sm, &params}});
  EXPECT_THROW(
      {
        try {
          checkMemoryPlan(plan, deviceWith(64 * kGiB, 512u << 20), std::nullopt);
        } catch (const MemoryError& e) {
          EXPECT_NE(std::string(e.what()).find("more than the device's largest allocation 512 MiB"), std::string::npos)
              << e.what();
          throw;
        }
      },
      MemoryError);
}

// The rasterizer's set-up records of a large scene (10 M triangles: 720 MB in one buffer) met the device's largest
// allocation only at the first draw (CL_INVALID_BUFFER_SIZE); the plan names them before any work.
TEST(MemoryPlan, RasterizerRecordsOfALargeSceneAreChecked) {
  const TechniqueInfo& pcss = findTechnique("pcss");
  Params params(pcss.params);
  const PlannedScene scene{10'000'000, 5'000'000};
  const MemoryPlan plan =
      planFrame(cameraOf(1024, 1024), {{LightType::Spot, &pcss, &params}}, FrameDownload::Image, scene);
  const MemoryPlan bare = planFrame(cameraOf(1024, 1024), {{LightType::Spot, &pcss, &params}});
  EXPECT_GE(plan.deviceBytes() - bare.deviceBytes(), uint64_t{10'000'000} * 64);  // records alone
  try {
    checkMemoryPlan(plan, deviceWith(64 * kGiB, 512u << 20), std::nullopt);
    ADD_FAILURE() << "a 720 MB buffer passed a 512 MiB largest allocation";
  } catch (const MemoryError& e) {
    EXPECT_NE(std::string(e.what()).find("rasterizer: scene and queues needs one buffer of"), std::string::npos)
        << e.what();
  }
  EXPECT_NO_THROW(checkMemoryPlan(plan, deviceWith(64 * kGiB, 1024u << 20), std::nullopt));
}

TEST(MemoryPlan, ParsesSizes) {
  EXPECT_EQ(parseMemorySize("4GiB", "x"), 4 * kGiB);
  EXPECT_EQ(parseMemorySize("512m", "x"), uint64_t{512} << 20);
  EXPECT_EQ(parseMemorySize("1.5G", "x"), 3 * kGiB / 2);
  EXPECT_EQ(parseMemorySize("65536", "x"), 65536u);
  for (const char* bad : {"", "GiB", "-1G", "0", "1Q", "nan", "inf", "1e30G", "4 GiB"})
    EXPECT_THROW(parseMemorySize(bad, "--memory-limit"), std::invalid_argument) << bad;
  EXPECT_EQ(formatBytes(1536), "1.5 KiB");
  EXPECT_EQ(formatBytes(17), "17 bytes");
}

TEST(FrameCheck, CoordinatesOutsideTheRangeNameTheirOwner) {
  const Scene scene = makeProcedural("box", {});
  Camera camera = cameraOf(16, 16);
  camera.eye = glm::vec3(3e38f, 0, 0);
  EXPECT_THROW(checkFrameRange(scene, camera, {}), std::invalid_argument);
  camera.eye = glm::vec3(0, 0, 5);
  EXPECT_NO_THROW(checkFrameRange(scene, camera, {}));
  Light light;
  light.type = LightType::Point, light.position = glm::vec3(0, -1e30f, 0);
  try {
    checkFrameRange(scene, camera, std::vector<Light>{light});
    FAIL() << "not refused";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("position (0, -1e+30, 0) is outside +-1e+18"), std::string::npos) << e.what();
  }
  EXPECT_THROW(checkFrameRange(scene, cameraOf(8193, 16), {}), std::invalid_argument);
}

TEST(FrameCheck, AFrameThatSeesNothingWarns) {
  Scene flat = makeProcedural("box", {});
  for (glm::vec3& p : flat.positions) p = glm::vec3(0.0f);  // every node scaled to 0
  const std::vector<float> background(16, 0.0f), covered = {0.0f, 1.0f};
  const auto warning = emptyFrameWarning(flat, cameraOf(4, 4), background);
  ASSERT_TRUE(warning.has_value());
  EXPECT_NE(warning->find("sees no surface"), std::string::npos);
  EXPECT_NE(warning->find("no extent"), std::string::npos);
  EXPECT_FALSE(emptyFrameWarning(flat, cameraOf(2, 1), covered).has_value());
}

// An area light the geometry comes within reach of warns, naming the distance; a light clear of it, a hard light and
// a sun do not. builtin:box: a unit box on the ground (y = 0), x and z in [-0.5, 0.5].
TEST(FrameCheck, AnAreaLightTheSceneReachesIntoWarns) {
  const Scene box = makeProcedural("box", {});
  auto warns = [&](const std::string& spec) { return lightReachWarning(box, parseLight(spec)); };
  const auto inside = warns("point:0,0.5,0.6:0.3");  // 0.1 from the box's face z = 0.5
  ASSERT_TRUE(inside.has_value());
  EXPECT_NE(inside->find("within 0.1 of its centre, inside its radius 0.3"), std::string::npos) << *inside;
  EXPECT_NE(inside->find("sphere"), std::string::npos);
  const auto engulfs = warns("point:0,5,0:1e17");
  ASSERT_TRUE(engulfs.has_value());
  EXPECT_NE(engulfs->find("within 5 of its centre"), std::string::npos) << *engulfs;
  const auto edge = warns("spot:0.7,1.2,0:0,0,0:60:0.3");  // 0.28 from the edge (0.5, 1, z) of the box's top
  ASSERT_TRUE(edge.has_value());
  EXPECT_NE(edge->find("disk"), std::string::npos);
  EXPECT_FALSE(warns("point:0,0.5,1.0:0.3").has_value());      // 0.5 from the face: out of reach
  EXPECT_FALSE(warns("point:0,0.5,0.6").has_value());          // a hard light has no extent
  EXPECT_FALSE(warns("spot:0,3,0:0,0,0:60:0.5").has_value());  // 2 above the top
  EXPECT_FALSE(warns("dir:0,-1,0:5").has_value());             // a sun's radius is an angle
  EXPECT_FALSE(lightReachWarning(Scene{}, parseLight("point:0,0,0:1")).has_value());
}

}  // namespace memory_plan_test
}  // namespace penumbra
