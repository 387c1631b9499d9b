// The reference frame: rasterize the G-buffer (host/views/views.h cameraView, as the Renderer does, so the
// pixels match `render` exactly), turn covered pixels into receivers with their triangle's geometric normal,
// trace each light, scatter back (background: visibility 1, stderr 0) and shade the preview with the same kernels.
#include "tools/reference/reference.h"

#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cmath>

#include "host/eval/metrics.h"
#include "host/pipeline/frame_image.h"
#include "host/scene/light_names.h"
#include "host/views/views.h"
#include "raster/rasterizer.h"
#include "host/views/raster_scene.h"

namespace penumbra::reference {
namespace {

// The geometric normal of the triangle a pixel sees (its shading normal if the triangle is degenerate).
glm::vec3 geometricNormal(const Scene& scene, uint32_t triangle, const cl_float4& shading) {
  const glm::uvec3 t = scene.triangles[triangle];
  const glm::vec3 n =
      glm::cross(scene.positions[t[1]] - scene.positions[t[0]], scene.positions[t[2]] - scene.positions[t[0]]);
  const float len = glm::length(n);
  return len > 0.0f && std::isfinite(len) ? n / len : glm::vec3(shading.s[0], shading.s[1], shading.s[2]);
}

struct Receivers {
  std::vector<ShadowPoint> points;
  std::vector<size_t> pixels;  // G-buffer index (rows bottom-up) of each point
};

Receivers receivers(Context& ctx, const Scene& scene, const GBuffer& gbuffer, const std::vector<cl_float4>& position,
                    const std::vector<cl_float4>& normal) {
  const std::vector<uint32_t> triangle = gbuffer.triangleId.download(ctx);
  Receivers r;
  for (size_t i = 0; i < position.size(); ++i) {
    if (position[i].s[3] == 0.0f || triangle[i] >= scene.triangles.size()) continue;
    r.points.push_back(
        {{position[i].s[0], position[i].s[1], position[i].s[2]}, geometricNormal(scene, triangle[i], normal[i])});
    r.pixels.push_back(i);
  }
  return r;
}

void summarise(ReferenceResult& result, const std::vector<float>& standardError) {
  double sum = 0, sumSq = 0, max = 0;
  for (float e : standardError) sum += e, sumSq += double{e} * e, max = std::max(max, double{e});
  const double n = static_cast<double>(std::max<size_t>(standardError.size(), 1));
  result.stderrMean = sum / n;
  result.stderrRms = std::sqrt(sumSq / n);
  result.stderrMax = max;
}

}  // namespace

ReferenceResult renderReference(Context& ctx, const Scene& scene, const Camera& camera, const Light& light,
                                const TraceSettings& settings) {
  return renderReference(ctx, scene, camera, std::vector<Light>{light}, settings);
}

ReferenceRaster::ReferenceRaster(Context& ctx, const Scene& scene) : ctx_(ctx), scene_(scene), raster_(ctx) {
  uploadScene(raster_, scene);
}

ReferenceResult renderReference(Context& ctx, const Scene& scene, const Camera& camera,
                                const std::vector<Light>& lights, const TraceSettings& settings) {
  using Clock = std::chrono::steady_clock;
  const Clock::time_point start = Clock::now();
  ReferenceRaster raster(ctx, scene);
  const double setUp = std::chrono::duration<double>(Clock::now() - start).count();
  ReferenceResult result = renderReference(raster, camera, lights, settings);
  result.rasterSeconds += setUp;  // a single frame pays for its rasterizer
  return result;
}

ReferenceResult renderReference(ReferenceRaster& peer, const Camera& camera, const std::vector<Light>& lights,
                                const TraceSettings& settings) {
  if (lights.empty()) throw std::invalid_argument("renderReference: no lights");
  using Clock = std::chrono::steady_clock;
  Context& ctx = peer.ctx();
  const Scene& scene = peer.scene();
  ReferenceResult result;
  const Bounds bounds = scene.bounds();
  const Clock::time_point start = Clock::now();
  GBuffer& gbuffer = peer.gbuffer();
  peer.raster().drawGBuffer(cameraView(camera, bounds), gbuffer);
  const std::vector<cl_float4> position = gbuffer.position.download(ctx), normal = gbuffer.normal.download(ctx);
  const Receivers r = receivers(ctx, scene, gbuffer, position, normal);
  result.rasterSeconds = std::chrono::duration<double>(Clock::now() - start).count();

  const ShadowTracer tracer(scene);
  const size_t count = static_cast<size_t>(gbuffer.width) * static_cast<size_t>(gbuffer.height);
  std::vector<Buffer<float>> visibilityGpu;
  std::vector<std::vector<float>> standardErrors;
  TraceResult first;
  // izb's light pattern is keyed by the G-buffer pixel.
  const std::vector<uint32_t> keys(r.pixels.begin(), r.pixels.end());
  TraceSettings keyed = settings;
  keyed.patternKeys = keys;
  for (size_t l = 0; l < lights.size(); ++l) {
    TraceResult traced = tracer.trace(r.points, lights[l], keyed);
    std::vector<float> visibility(count, 1.0f), standardError(count, 0.0f);
    for (size_t k = 0; k < r.pixels.size(); ++k) {
      visibility[r.pixels[k]] = traced.visibility[k];
      standardError[r.pixels[k]] = traced.standardError[k];
    }
    visibilityGpu.emplace_back(ctx, std::span<const float>(visibility));
    standardErrors.push_back(std::move(standardError));
    result.traceSeconds += traced.seconds;
    result.rays += traced.rays;
    if (l == 0) first = std::move(traced);
  }
  std::vector<LightVisibility> layers;
  for (size_t l = 0; l < lights.size(); ++l) layers.push_back({&lights[l], &visibilityGpu[l]});
  result.image = frameImage(ctx, gbuffer, layers, camera, bounds);
  result.image.add("stderr.Y", standardErrors[0]);
  result.image.add(kLitChannel, litMask(position, normal, camera, lights[0]));
  for (size_t l = 0; l < lights.size(); ++l) {
    const std::string layer = lightLayer(lights[l]);
    result.image.add(lightChannel("stderr", layer), std::move(standardErrors[l]));
    result.image.add(lightChannel("lit", layer), litMask(position, normal, camera, lights[l]));
  }
  result.image.flipRows();  // the rasterizer's row 0 is the bottom row

  const TraceResult& traced = first;
  result.covered = r.points.size();
  result.spp = traced.spp;
  result.threads = traced.threads;
  result.buildSeconds = tracer.buildSeconds();
  summarise(result, traced.standardError);
  auto& attributes = result.image.attributes();
  attributes["penumbra:technique"] = "reference";
  attributes["penumbra:parameters"] =
      fmt::format("spp={} seed={} ray-offset={}", result.spp, settings.seed, ShadowTracer::kRayOffset);
  auto& numbers = result.image.numbers();  // EXR doubles (nothing read the former strings of the same names)
  numbers["penumbra:stderr-mean"] = result.stderrMean;
  numbers["penumbra:stderr-rms"] = result.stderrRms;
  numbers["penumbra:stderr-max"] = result.stderrMax;
  numbers["penumbra:rays"] = static_cast<double>(result.rays);
  numbers["penumbra:spp"] = static_cast<double>(result.spp);
  return result;
}

}  // namespace penumbra::reference
