// One frame: G-buffer, technique, preview shading, download into an Image.
#include "host/pipeline/renderer.h"

#include <fmt/format.h>

#include <cmath>

#include "host/cl/kernel.h"
#include "host/pipeline/views.h"
#include "host/techniques/registry.h"

namespace penumbra {
namespace {

constexpr size_t kShadeGroup = 64;

// Splits the xyz of a float4 buffer into named channels ("P.X", "P.Y", "P.Z").
void addVectorChannels(Image& image, const std::vector<cl_float4>& data, const std::string& layer) {
  static const char* kAxes[] = {"X", "Y", "Z"};
  for (int c = 0; c < 3; ++c) {
    std::vector<float> channel(data.size());
    for (size_t i = 0; i < data.size(); ++i) channel[i] = data[i].s[c];
    image.add(fmt::format("{}.{}", layer, kAxes[c]), std::move(channel));
  }
}

void addPreview(Image& image, const std::vector<cl_float4>& rgba) {
  static const char* kNames[] = {"R", "G", "B", "A"};
  for (int c = 0; c < 4; ++c) {
    std::vector<float> channel(rgba.size());
    for (size_t i = 0; i < rgba.size(); ++i) channel[i] = rgba[i].s[c];
    image.add(kNames[c], std::move(channel));
  }
}

}  // namespace

Renderer::Renderer(Context& ctx, const Scene& scene) : ctx_(ctx), scene_(scene), raster_(ctx) {
  raster_.setScene(scene);
}

RenderResult Renderer::render(const Camera& camera, const Light& light, const TechniqueInfo& technique,
                              const Params& params) {
  Profiler profiler;
  ProfilerScope scope(ctx_, profiler);
  const Bounds bounds = scene_.bounds();
  raster_.drawGBuffer(cameraView(camera, bounds), gbuffer_);
  const uint32_t count = static_cast<uint32_t>(camera.width) * static_cast<uint32_t>(camera.height);

  Buffer<float> visibility(ctx_, count);
  std::unique_ptr<Technique> shadows = technique.create(params);
  const ReceiverBounds receivers =
      reduceReceivers(ctx_, gbuffer_, lightEyeMatrix(light, bounds), light.type == LightType::Spot);
  ShadowFrame frame{ctx_, raster_, scene_, light, camera, gbuffer_, receivers};
  shadows->render(frame, visibility);

  // The preview needs only the light's position, axis and cone, not a map: a 1-texel view suffices.
  LightView shading = fitLightView(light, bounds, 1);
  Buffer<LightViewGpu> shadingGpu(ctx_, std::span<const LightViewGpu>(&shading.gpu, 1), CL_MEM_READ_ONLY);
  Buffer<cl_float4> rgba(ctx_, count);
  const cl_float4 eye = {{camera.eye.x, camera.eye.y, camera.eye.z, 1.0f}};
  const float cosHalfFov = light.type == LightType::Spot ? std::cos(glm::radians(light.fovDeg) * 0.5f) : -1.0f;
  Kernel shade(ctx_, "kernels/shade.cl", "shade_preview", "shade");
  shade.args(gbuffer_.position, gbuffer_.normal, visibility, count, shadingGpu, eye, cosHalfFov, rgba)
      .launch(count, kShadeGroup);

  RenderResult result;
  Image& image = result.image;
  image = Image(camera.width, camera.height);
  addPreview(image, rgba.download(ctx_));
  image.add("visibility.Y", visibility.download(ctx_));
  addVectorChannels(image, gbuffer_.position.download(ctx_), "P");
  addVectorChannels(image, gbuffer_.normal.download(ctx_), "N");
  image.add("depth.Z", gbuffer_.depth.download(ctx_));
  shadows->addDebugChannels(ctx_, image);
  image.flipRows();  // the rasterizer's row 0 is the bottom row

  auto& attributes = image.attributes();
  attributes.insert(frame.attributes.begin(), frame.attributes.end());
  attributes["penumbra:technique"] = technique.name;
  attributes["penumbra:parameters"] = params.describe();
  attributes["penumbra:device"] =
      fmt::format("{} ({}, {})", ctx_.info().name, ctx_.info().platformName, ctx_.info().driverVersion);
  attributes["penumbra:light"] = light.describe();
  attributes["penumbra:camera"] = fmt::format("{},{},{}:{},{},{}:{}", camera.eye.x, camera.eye.y, camera.eye.z,
                                              camera.target.x, camera.target.y, camera.target.z, camera.fovYDeg);
  result.passes = profiler.resolve();
  return result;
}

}  // namespace penumbra
