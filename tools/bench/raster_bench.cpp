// Google Benchmark of the binned rasterizer (raster/): device time per kernel from OpenCL profiling events (warm-up
// and queue growth excluded) and triangles/s, for shadow maps (orthographic light views) of FlightHelmet on a
// ground plane, the 1M-triangle MetalRoughSpheres and a procedural 262k-triangle field of spheres, at 2048^2 and
// 4096^2, plus a perspective camera view; and the sphere field with every triangle alpha-tested (its cost beside the
// opaque field's). Device: PENUMBRA_DEVICE (or "auto"). Scenes: PENUMBRA_SCENES_DIR, else
// ../shared/scenes beside the source tree; missing files skip their cases.
// Beside each case, peer_gl/<same name> (built when glvnd's OpenGL + EGL are found) draws the same triangles with the
// same clip matrix depth-only through a headless OpenGL driver (tools/bench/gl_depth_peer.h): Mesa's llvmpipe on a
// CPU machine, the vendor's driver on a GPU one. On the CPU machine both sides get every core: PoCL by default,
// llvmpipe's rasterizer threads default to the CPU count (LP_NUM_THREADS overrides it).
//   build/tools/raster_bench --benchmark_counters_tabular=true
// PENUMBRA_RASTER_BENCH_HASH=1 prints a hash of each case's targets (layout changes must keep them).
#include <benchmark/benchmark.h>
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <glm/gtc/matrix_transform.hpp>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "host/cl/context.h"
#include "host/cl/profiler.h"
#include "host/scene/gltf_loader.h"
#include "raster/rasterizer.h"
#ifdef PENUMBRA_GL_PEER
#include "tools/bench/gl_depth_peer.h"
#include "host/views/raster_scene.h"
#endif

namespace penumbra {
namespace {

std::string scenePath(const std::string& name) {
  for (const std::string& dir :
       {std::string(PENUMBRA_SOURCE_DIR) + "/scenes", std::string(PENUMBRA_SOURCE_DIR) + "/../shared/scenes"})
    if (std::filesystem::exists(dir + "/" + name)) return dir + "/" + name;
  return {};
}

// A square ground plane under the scene, three times its extent.
Scene withGround(Scene scene) {
  const Bounds b = scene.bounds();
  const float r = 1.5f * glm::length(b.max - b.min), y = b.min.y - 0.01f * (b.max.y - b.min.y);
  const glm::vec3 c = b.center();
  const uint32_t base = static_cast<uint32_t>(scene.positions.size());
  for (glm::vec2 d : {glm::vec2(-1, -1), glm::vec2(1, -1), glm::vec2(1, 1), glm::vec2(-1, 1)}) {
    scene.positions.emplace_back(c.x + r * d.x, y, c.z - r * d.y);
    scene.normals.emplace_back(0, 1, 0);
  }
  scene.triangles.emplace_back(base, base + 1, base + 2);
  scene.triangles.emplace_back(base, base + 2, base + 3);
  scene.objectIds.resize(scene.triangles.size(), static_cast<uint32_t>(scene.objectNames.size()));
  scene.objectNames.push_back("ground");
  if (!scene.materials.empty()) {  // a glTF scene's triangles have materials: the ground gets the plain one
    scene.materialIds.resize(scene.triangles.size(), static_cast<uint32_t>(scene.materials.size()));
    scene.materials.push_back(plainMaterial());
  }
  if (!scene.uvs.empty()) scene.uvs.resize(scene.positions.size(), glm::vec2(0.0f));
  return scene;
}

// The sphere field with every triangle alpha-tested (MASK, LINEAR, REPEAT): texture coordinates (phi / pi, theta / pi)
// over a 64^2 checker of 8^2-texel squares, alpha 0 or 1, so about half of every sphere is cut away. Its cost beside
// the opaque field's is the price of the alpha test.
Scene maskedSphereField(Scene s) {
  s.alphaTextures.push_back({"checker", 64, 64, 0});
  for (int y = 0; y < 64; ++y)
    for (int x = 0; x < 64; ++x) s.alphaTexels.push_back(((x / 8 + y / 8) % 2) != 0 ? 255 : 0);
  Material mask;
  mask.name = "checker";
  mask.alphaMode = AlphaMode::kMask;
  mask.alphaTexture = 0;
  s.materials = {mask};
  s.materialIds.assign(s.triangles.size(), 0);
  s.uvs.clear();
  for (size_t i = 0; i < s.positions.size(); ++i) {
    const glm::vec3 d = s.normals[i];  // the unit sphere direction of the vertex
    s.uvs.emplace_back(std::atan2(d.z, d.x) / glm::pi<float>(), std::acos(std::clamp(d.y, -1.0f, 1.0f)) /
                                                                      glm::pi<float>());
  }
  return s;
}

// 16 x 16 UV spheres of 16 x 32 quads, two triangles each (the pole ones degenerate): 262,144 triangles.
Scene sphereField() {
  Scene s;
  const int stacks = 16;
  for (int gx = 0; gx < 16; ++gx)
    for (int gz = 0; gz < 16; ++gz) {
      const glm::vec3 centre(gx * 2.5f, 1.0f, gz * 2.5f);
      const uint32_t base = static_cast<uint32_t>(s.positions.size());
      for (int i = 0; i <= stacks; ++i)
        for (int j = 0; j <= 32; ++j) {
          const float theta = glm::pi<float>() * i / stacks, phi = 2 * glm::pi<float>() * j / 32;
          const glm::vec3 d(std::sin(theta) * std::cos(phi), std::cos(theta), std::sin(theta) * std::sin(phi));
          s.positions.push_back(centre + d);
          s.normals.push_back(d);
        }
      for (int i = 0; i < stacks; ++i)
        for (int j = 0; j < 32; ++j) {
          const uint32_t a = base + i * 33 + j, b = a + 33;
          s.triangles.emplace_back(a, a + 1, b);
          s.triangles.emplace_back(a + 1, b + 1, b);
        }
    }
  s.objectIds.assign(s.triangles.size(), 0);
  s.objectNames = {"spheres"};
  return s;
}

// A directional light's shadow map: orthographic, fitted to the scene's bounding sphere.
RasterView lightView(const Scene& scene, int size) {
  const Bounds b = scene.bounds();
  const glm::vec3 c = b.center(), dir = glm::normalize(glm::vec3(0.35f, -1.0f, 0.25f));
  const float r = b.radius();
  RasterView v;
  v.view = glm::lookAt(c - 2.0f * r * dir, c, glm::vec3(0, 0, 1));
  v.projection = glm::ortho(-r, r, -r, r, 0.5f * r, 3.5f * r);
  v.width = v.height = size;
  v.depthMode = DepthMode::kViewZ;
  return v;
}

RasterView cameraView(const Scene& scene, int size) {
  const Bounds b = scene.bounds();
  const glm::vec3 c = b.center();
  const float r = b.radius();
  RasterView v;
  v.view = glm::lookAt(c + glm::vec3(0.6f, 0.5f, 1.2f) * r, c, glm::vec3(0, 1, 0));
  v.projection = glm::perspective(glm::radians(50.0f), 1.0f, 0.05f * r, 6.0f * r);
  v.width = v.height = size;
  return v;
}

// FNV-1a over the depth and triangle-id targets' bytes: with PENUMBRA_RASTER_BENCH_HASH set, each case prints it
// once, so a change to the kernels can be checked to leave every output bit as it was.
uint64_t outputHash(Context& ctx, const RasterTargets& targets) {
  uint64_t h = 14695981039346656037ull;
  auto mix = [&h](const void* data, size_t bytes) {
    for (size_t i = 0; i < bytes; ++i) h = (h ^ static_cast<const unsigned char*>(data)[i]) * 1099511628211ull;
  };
  const std::vector<float> depth = targets.depth.download(ctx);
  const std::vector<uint32_t> ids = targets.triangleId.download(ctx);
  mix(depth.data(), depth.size() * sizeof(float));
  mix(ids.data(), ids.size() * sizeof(uint32_t));
  return h;
}

void addCase(Context& ctx, const std::string& name, std::shared_ptr<const Scene> scene, RasterView view) {
  benchmark::RegisterBenchmark(
      fmt::format("raster/{}/{}", name, view.width).c_str(),
      [&ctx, name, scene, view](benchmark::State& state) {
        Rasterizer raster(ctx);
        uploadScene(raster, *scene);
        RasterTargets targets;
        raster.draw(view, targets);  // warm-up: builds kernels, grows the queues
        std::map<std::string, double> perKernel;
        double totalMs = 0;
        for (auto _ : state) {
          Profiler profiler;
          ProfilerScope scope(ctx, profiler);
          raster.draw(view, targets);
          double ms = 0;
          for (const PassTime& pass : profiler.resolve()) {
            ms += pass.ms;  // kernels, the counter clears and the counter read-back
            perKernel[pass.name] += pass.ms;
          }
          totalMs += ms;
          state.SetIterationTime(ms * 1e-3);
        }
        const double n = static_cast<double>(state.iterations());
        for (const auto& [pass, ms] : perKernel)
          state.counters[pass.substr(pass.find('/') + 1) + "_us"] = benchmark::Counter(ms * 1e3 / n);
        state.counters["Mtri/s"] = benchmark::Counter(scene->triangleCount() / (totalMs * 1e-3 / n) * 1e-6);
        state.counters["triangles"] = benchmark::Counter(static_cast<double>(scene->triangleCount()));
        state.counters["set_up"] = benchmark::Counter(static_cast<double>(raster.stats().trianglesSetUp));
        state.counters["tile_entries"] = benchmark::Counter(static_cast<double>(raster.stats().tileEntries));
        if (std::getenv("PENUMBRA_RASTER_BENCH_HASH") != nullptr)
          std::fprintf(stderr, "output hash %s/%d: %016llx\n", name.c_str(), view.width,
                       static_cast<unsigned long long>(outputHash(ctx, targets)));
      })
      ->UseManualTime()
      ->Unit(benchmark::kMicrosecond);
}

#ifdef PENUMBRA_GL_PEER
// The fraction of pixels that both renderers leave covered, or both leave empty: GL clears to depth 1, our
// targets to +INFINITY. Only edge pixels may differ (fill-rule ties, float vs double vertex transforms).
double coverageAgreement(const std::vector<float>& gl, const std::vector<float>& ours, size_t& differ) {
  differ = 0;
  for (size_t i = 0; i < gl.size() && i < ours.size(); ++i) differ += (gl[i] < 1.0f) != std::isfinite(ours[i]);
  differ += std::max(gl.size(), ours.size()) - std::min(gl.size(), ours.size());
  return 1.0 - static_cast<double>(differ) / static_cast<double>(std::max<size_t>(gl.size(), 1));
}

// One peer case: warm-up, then per frame the wall clock and the GL_TIME_ELAPSED query, both reported. The iteration
// time is the query on a GPU driver (device time, like our profiling events) and the wall clock on Mesa's CPU
// rasterizers, where the query reads far less than the frame takes. Then our rasterizer draws the same view once
// for the coverage cross-check.
void runPeer(benchmark::State& state, Context& ctx, GlDepthPeer& peer, const Scene& scene, const RasterView& view) {
  const glm::mat4 clip = rasterClipMatrix(view);  // the float matrix our setup starts from
  peer.setScene(scene);
  peer.draw(clip, view.width, view.height);  // warm-up: shader compile, first-touch of the target
  const bool wallClock = peer.software();
  double wallMs = 0, queryMs = 0, timedMs = 0;
  bool query = true;  // every frame had a timer-query result
  for (auto _ : state) {
    const GlFrameTime t = peer.draw(clip, view.width, view.height);
    const double ms = t.queryMs < 0 || wallClock ? t.wallMs : t.queryMs;
    wallMs += t.wallMs, queryMs += t.queryMs, timedMs += ms;
    query = query && t.queryMs >= 0;
    state.SetIterationTime(ms * 1e-3);
  }
  const double n = static_cast<double>(state.iterations());
  state.counters["Mtri/s"] = benchmark::Counter(scene.triangleCount() / (timedMs * 1e-3 / n) * 1e-6);
  state.counters["wall_us"] = benchmark::Counter(wallMs * 1e3 / n);
  if (query) state.counters["gpu_query_us"] = benchmark::Counter(queryMs * 1e3 / n);
  state.counters["triangles"] = benchmark::Counter(static_cast<double>(scene.triangleCount()));
  Rasterizer raster(ctx);
  uploadScene(raster, scene);
  RasterTargets targets;
  raster.draw(view, targets);
  size_t differ = 0;
  state.counters["coverage_agree"] =
      benchmark::Counter(coverageAgreement(peer.readDepth(), targets.depth.download(ctx), differ));
  state.counters["coverage_differ"] = benchmark::Counter(static_cast<double>(differ));
}

void addPeerCase(Context& ctx, GlDepthPeer* peer, const std::string& unavailable, const std::string& name,
                 std::shared_ptr<const Scene> scene, RasterView view) {
  benchmark::RegisterBenchmark(fmt::format("peer_gl/{}/{}", name, view.width).c_str(),
                               [&ctx, peer, unavailable, scene, view](benchmark::State& state) {
                                 if (peer == nullptr) return state.SkipWithError(unavailable.c_str());
                                 try {
                                   runPeer(state, ctx, *peer, *scene, view);
                                 } catch (const std::exception& e) {
                                   state.SkipWithError(e.what());
                                 }
                               })
      ->UseManualTime()
      ->Unit(benchmark::kMicrosecond);
}
#endif

}  // namespace
}  // namespace penumbra

int main(int argc, char** argv) {
  using namespace penumbra;
  benchmark::Initialize(&argc, argv);
  Context ctx;
  std::fprintf(stderr, "device: %s (%s)\n", ctx.info().name.c_str(), ctx.info().platformName.c_str());
#ifdef PENUMBRA_GL_PEER
  // Made here, on the thread that runs the benchmarks: the GL context is current on this thread only.
  std::unique_ptr<GlDepthPeer> peer;
  std::string unavailable;
  try {
    peer = std::make_unique<GlDepthPeer>();
    std::fprintf(stderr, "peer_gl: %s (%s)\n", peer->renderer().c_str(), peer->version().c_str());
  } catch (const std::exception& e) {
    unavailable = e.what();
    std::fprintf(stderr, "peer_gl: unavailable: %s\n", unavailable.c_str());
  }
#endif
  auto add = [&](const std::string& name, const std::shared_ptr<const Scene>& scene, const RasterView& view) {
    addCase(ctx, name, scene, view);
#ifdef PENUMBRA_GL_PEER
    addPeerCase(ctx, peer.get(), unavailable, name, scene, view);
#endif
  };
  std::vector<std::pair<std::string, std::shared_ptr<const Scene>>> scenes;
  if (std::string p = scenePath("FlightHelmet.glb"); !p.empty())
    scenes.emplace_back("FlightHelmetGround", std::make_shared<const Scene>(withGround(loadGltf(p))));
  if (std::string p = scenePath("MetalRoughSpheresNoTextures.glb"); !p.empty())
    scenes.emplace_back("MetalRoughSpheres", std::make_shared<const Scene>(loadGltf(p)));
  scenes.emplace_back("SphereField262k", std::make_shared<const Scene>(sphereField()));
  for (const auto& [name, scene] : scenes)
    for (int size : {2048, 4096}) add("shadow/" + name, scene, lightView(*scene, size));
  for (const auto& [name, scene] : scenes) add("camera/" + name, scene, cameraView(*scene, 2048));
  const auto masked = std::make_shared<const Scene>(maskedSphereField(sphereField()));
  // No OpenGL peer: it draws depth only, without the alpha test.
  addCase(ctx, "shadow/SphereField262kMasked", masked, lightView(*masked, 2048));
  addCase(ctx, "camera/SphereField262kMasked", masked, cameraView(*masked, 2048));
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
