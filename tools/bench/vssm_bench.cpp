// Google Benchmark of VSSM (Yang et al. 2010) against PCSS on the same scene, camera and light at several light
// sizes: device time per pass from OpenCL profiling events (warm-up excluded) and accuracy against brute-force PCSS
// (32 x 32 search and filter taps). The paper claims VSSM is at least an order of magnitude faster than PCSS for
// large penumbrae; the counters show where we stand.
//   build/tools/vssm_bench --image=1920x1080 --map=2048 --benchmark_counters_tabular=true
// Defaults: 640x360, 1024^2 map, builtin:staircase with its spot light at radius 0.1 .. 0.8. Device:
// PENUMBRA_DEVICE (or "auto").
#include <benchmark/benchmark.h>
#include <fmt/format.h>

#include <cmath>
#include <cstdio>
#include <cstring>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "host/cl/context.h"
#include "host/pipeline/renderer.h"
#include "host/scene/procedural.h"
#include "host/techniques/technique.h"

namespace penumbra {
namespace {

struct Setup {
  Context ctx;
  Scene scene = makeProcedural("staircase");
  int width = 640, height = 360, map = 1024;
  std::map<float, std::vector<float>> reference;  // visibility of brute-force PCSS per light radius
};

// PCSS may search and filter as far as VSSM does (vssm-max-radius defaults to 128 texels).
const std::pair<const std::string, std::string> kPcssReach{"pcss-max-radius", "128"};

struct Variant {
  std::string name, technique;
  std::map<std::string, std::string> params;
};

RenderResult render(Setup& s, float radius, const Variant& v) {
  Camera camera = s.scene.cameras.front();
  camera.width = s.width, camera.height = s.height;
  Light light = s.scene.lights.front();
  light.radius = radius;
  const TechniqueInfo& info = findTechnique(v.technique);
  Params params(info.params);
  params.set("map-size", std::to_string(s.map));
  for (const auto& [name, value] : v.params) params.set(name, value);
  Renderer renderer(s.ctx, s.scene);
  return renderer.render(camera, light, info, params);
}

// Device ms of the passes whose name starts with one of `prefixes` ("" = every pass but transfers and the preview).
double passMs(const RenderResult& r, const std::vector<std::string>& prefixes) {
  double ms = 0.0;
  for (const PassTime& pass : r.passes) {
    if (pass.name.rfind("transfer/", 0) == 0 || pass.name == "shade/shade_preview") continue;
    for (const std::string& p : prefixes)
      if (pass.name.rfind(p, 0) == 0) {
        ms += pass.ms;
        break;
      }
  }
  return ms;
}

const std::vector<float>& referenceFor(Setup& s, float radius) {
  auto it = s.reference.find(radius);
  if (it != s.reference.end()) return it->second;
  const Variant brute{"pcss32", "pcss", {{"pcss-search-taps", "32"}, {"pcss-filter-taps", "32"}, kPcssReach}};
  return s.reference[radius] = render(s, radius, brute).image.require("visibility.Y").data;
}

void run(benchmark::State& state, Setup& s, float radius, const Variant& v) {
  const std::vector<float>& ref = referenceFor(s, radius);
  RenderResult last = render(s, radius, v);  // warm-up: program builds, buffer growth
  double shade = 0, maps = 0, frame = 0;
  for (auto _ : state) {
    last = render(s, radius, v);
    const double ms = passMs(last, {""});
    shade += passMs(last, {"shade/"});
    maps += passMs(last, {"moments/", "sat/", "pyramid/", "vssm/"});
    frame += ms;
    state.SetIterationTime(ms * 1e-3);
  }
  const double n = double(state.iterations());
  const Image& image = last.image;
  const auto &vis = image.require("visibility.Y").data, &alpha = image.require("A").data;
  const auto &px = image.require("P.X").data, &py = image.require("P.Y").data, &pz = image.require("P.Z").data;
  const auto &nx = image.require("N.X").data, &ny = image.require("N.Y").data, &nz = image.require("N.Z").data;
  const ImageChannel* path = image.find("path.Z");
  const glm::vec3 lightPos = s.scene.lights.front().position;
  double err = 0, frontErr = 0;
  size_t pixels = 0, front = 0, subdivided = 0;
  for (size_t i = 0; i < vis.size(); ++i) {
    if (alpha[i] == 0.0f) continue;
    const double d = std::abs(double(vis[i]) - ref[i]);
    const glm::vec3 p(px[i], py[i], pz[i]), nrm(nx[i], ny[i], nz[i]);
    const bool facing = glm::dot(nrm, glm::normalize(lightPos - p)) > 0.1f;
    err += d, ++pixels;
    frontErr += facing ? d : 0.0, front += facing;
    if (path != nullptr) subdivided += path->data[i] == 3.0f;  // VSSM_PATH_SUBDIVIDED
  }
  state.counters["shade_ms"] = shade / n;                       // the visibility kernel
  state.counters["maps_ms"] = maps / n;                         // moments, SAT, HSM (VSSM only)
  state.counters["frame_ms"] = frame / n;                       // every pass: G-buffer, shadow map, maps, shading
  state.counters["mae"] = pixels ? err / double(pixels) : 0.0;  // against PCSS 32x32, every surface pixel
  state.counters["mae_lit_side"] = front ? frontErr / double(front) : 0.0;            // surfaces facing the light
  state.counters["subdivided"] = pixels ? double(subdivided) / double(pixels) : 0.0;  // share of surface pixels
}

void registerAll(Setup& s) {
  const std::vector<Variant> variants = {
      {"vssm_mixed", "vssm", {}},
      {"vssm_none", "vssm", {{"vssm-subdivision", "none"}}},
      {"vssm_uniform", "vssm", {{"vssm-subdivision", "uniform"}}},
      {"vssm_adaptive", "vssm", {{"vssm-subdivision", "adaptive"}}},
      {"pcss8", "pcss", {kPcssReach}},
      {"pcss16", "pcss", {{"pcss-search-taps", "16"}, {"pcss-filter-taps", "16"}, kPcssReach}},
  };
  for (float radius : {0.1f, 0.2f, 0.4f, 0.8f})
    for (const Variant& v : variants)
      benchmark::RegisterBenchmark(fmt::format("{}/radius:{}", v.name, radius).c_str(),
                                   [&s, radius, v](benchmark::State& state) { run(state, s, radius, v); })
          ->UseManualTime()
          ->Unit(benchmark::kMillisecond);
}

// --image=WxH and --map=N, removed from argv before Google Benchmark sees it.
void parseOwnFlags(int& argc, char** argv, Setup& s) {
  int kept = 1;
  for (int i = 1; i < argc; ++i) {
    if (std::sscanf(argv[i], "--image=%dx%d", &s.width, &s.height) == 2) continue;
    if (std::sscanf(argv[i], "--map=%d", &s.map) == 1) continue;
    argv[kept++] = argv[i];
  }
  argc = kept;
}

}  // namespace
}  // namespace penumbra

int main(int argc, char** argv) {
  penumbra::Setup setup;
  penumbra::parseOwnFlags(argc, argv, setup);
  benchmark::Initialize(&argc, argv);
  std::printf("device: %s; image %dx%d, map %d^2, builtin:staircase\n", setup.ctx.info().name.c_str(), setup.width,
              setup.height, setup.map);
  penumbra::registerAll(setup);
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
