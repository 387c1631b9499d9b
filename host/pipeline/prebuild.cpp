// prebuild(): each named technique or stage run once on a small input, so that its programs are built (or loaded
// from the disk cache) before the calls that need them.
#include "host/pipeline/prebuild.h"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <functional>
#include <map>
#include <optional>
#include <stdexcept>

#include "host/cl/buffer.h"
#include "host/cl/error.h"
#include "host/pipeline/renderer.h"
#include "host/scene/framing.h"
#include "host/scene/load.h"
#include "host/stages/blur.h"
#include "host/stages/moments.h"
#include "host/stages/pyramid.h"
#include "host/stages/reduce.h"
#include "host/stages/sat.h"
#include "host/techniques/technique.h"

namespace penumbra {
namespace {

constexpr uint32_t kSide = 16;  // the stages' input: 16x16 texels, a ramp of light depths

Buffer<float> rampDepth(Context& ctx) {
  std::vector<float> depth(size_t(kSide) * kSide);
  for (size_t i = 0; i < depth.size(); ++i) depth[i] = 0.25f + 0.5f * static_cast<float>(i) / depth.size();
  return Buffer<float>(ctx, std::span<const float>(depth));
}

using Events = std::vector<cl::Event>;

void add(Events& events, const cl::Event& event) { events.push_back(event); }
void add(Events& events, const Events& more) { events.insert(events.end(), more.begin(), more.end()); }

// Each stage waits for its own commands before its buffers go (a caller's queue is never finished).
void wait(const Events& events) {
  if (!events.empty()) clCheck(cl::WaitForEvents(events), "clWaitForEvents", {}, "prebuild");
}

void prebuildMoments(Context& ctx) {
  Events events;
  const Buffer<float> depth = rampDepth(ctx);
  for (MomentKind kind :
       {MomentKind::Vsm, MomentKind::Evsm2, MomentKind::Evsm4, MomentKind::Msm, MomentKind::Esm, MomentKind::Lvsm}) {
    MomentsConfig config;
    config.kind = kind;
    if (kind == MomentKind::Lvsm) config.layers = {{0.0f, 0.6f}, {0.4f, 1.0f}};
    Buffer<float> out(ctx, depth.size() * momentChannels(kind) * momentPlanes(config));
    add(events, computeMoments(ctx, depth, kSide, kSide, config, out));
    std::optional<Buffer<cl_half>> half;
    if (kind != MomentKind::Lvsm) {  // LVSM has no half storage
      config.storage = MomentStorage::Float16;
      add(events, computeMoments(ctx, depth, kSide, kSide, config, half.emplace(ctx, out.size())));
    }
    wait(events);  // before this kind's buffers go
  }
}

void prebuildBlur(Context& ctx) {
  Events events;
  for (uint32_t channels : {1u, 2u, 4u}) {
    const ImageShape shape{kSide, kSide, channels};
    Buffer<float> image(ctx, shape.count()), scratch(ctx, shape.count());
    image.fill(ctx, 0.5f);
    for (BlurFilter filter : {BlurFilter::Gaussian, BlurFilter::Box})
      for (BlurMethod method : {BlurMethod::Direct, BlurMethod::RunningSums}) {
        BlurConfig config;
        config.filter = filter, config.method = method;
        add(events, blur(ctx, image, image, scratch, shape, config));
      }
    wait(events);
  }
}

void prebuildSat(Context& ctx) {
  const ImageShape shape{kSide, kSide, 2};
  Buffer<float> image(ctx, shape.count()), offset(ctx, 4);
  image.fill(ctx, 0.5f);
  Events events;
  Buffer<float> f32(ctx, shape.count());
  add(events, computeSat(ctx, image, shape, f32, offset));
  Buffer<uint32_t> fixed32(ctx, shape.count());
  add(events, computeSat(ctx, image, shape, fixed32, offset));
  Buffer<uint64_t> fixed64(ctx, shape.count());
  add(events, computeSat(ctx, image, shape, fixed64, offset));
  std::optional<Buffer<double>> f64;
  if (ctx.info().fp64) add(events, computeSat(ctx, image, shape, f64.emplace(ctx, shape.count()), offset));
  wait(events);
}

void prebuildPyramid(Context& ctx) {
  const Buffer<float> depth = rampDepth(ctx);
  Buffer<cl_float2> minMax(ctx, pyramidLayout(kSide, kSide, 0).texels);
  Events events = computeMinMaxPyramid(ctx, depth, kSide, kSide, minMax);
  const ImageShape shape{kSide, kSide, 2};
  Buffer<float> base(ctx, shape.count()), mips(ctx, pyramidLayout(kSide, kSide, 1).texels * shape.channels);
  base.fill(ctx, 0.5f);
  add(events, computeMomentMips(ctx, base, shape, mips));
  wait(events);
}

void prebuildReduce(Context& ctx) {
  const Buffer<float> x = rampDepth(ctx);
  Buffer<float> w(ctx, x.size());
  w.fill(ctx, 1.0f);
  const std::vector<float> splits = {0.5f};
  const Buffer<float> boundaries(ctx, std::span<const float>(splits));
  Buffer<LloydStats> stats(ctx, 2);
  wait(reduceLloydStats(ctx, x, w, x.size(), boundaries, 2, stats));
}

// A 32x24 frame of builtin:box under its own area light, the technique at its defaults.
void prebuildTechnique(Context& ctx, const std::string& name) {
  static const Scene scene = loadScene("builtin:box");
  Camera camera = scene.cameras.empty() ? framingCamera(scene.bounds()) : scene.cameras.front();
  camera.width = 32, camera.height = 24;
  const Light light = scene.lights.empty() ? framingLight(scene.bounds()) : scene.lights.front();
  const TechniqueInfo& technique = findTechnique(name);
  Renderer renderer(ctx, scene);
  renderer.render(camera, light, technique, Params(technique.params));
}

const std::map<std::string, std::function<void(Context&)>>& stages() {
  static const std::map<std::string, std::function<void(Context&)>> table = {
      {"moments", prebuildMoments}, {"blur", prebuildBlur},     {"sat", prebuildSat},
      {"pyramid", prebuildPyramid}, {"reduce", prebuildReduce},
  };
  return table;
}

}  // namespace

std::vector<std::string> prebuildNames() {
  std::vector<std::string> names;
  for (const TechniqueInfo& technique : techniques()) names.push_back(technique.name);
  for (const auto& [name, run] : stages()) names.push_back(name);
  names.push_back("all");
  return names;
}

void prebuild(Context& ctx, const std::vector<std::string>& names) {
  const std::vector<std::string> known = prebuildNames();
  std::vector<std::string> items;
  for (const std::string& name : names) {
    if (std::find(known.begin(), known.end(), name) == known.end())
      throw std::invalid_argument(
          fmt::format("prebuild: unknown item \"{}\" (known: {})", name, fmt::join(known, ", ")));
    if (name == "all") {
      items.insert(items.end(), known.begin(), known.end() - 1);
    } else {
      items.push_back(name);
    }
  }
  for (const std::string& item : items) {
    if (const auto stage = stages().find(item); stage != stages().end()) {
      stage->second(ctx);
    } else {
      prebuildTechnique(ctx, item);  // a render waits for its own commands
    }
  }
}

}  // namespace penumbra
