// Preview shading (one kernel launch, stage "shade") and the download of the G-buffer into named channels.
#include "host/pipeline/frame_image.h"

#include <fmt/format.h>

#include <cmath>
#include <string>
#include <vector>

#include "host/cl/kernel.h"
#include "host/pipeline/views.h"

namespace penumbra {
namespace {

constexpr size_t kShadeGroup = 64;

// Component `c` of every element of a float4 buffer as one channel.
std::vector<float> component(const std::vector<cl_float4>& data, int c) {
  std::vector<float> channel(data.size());
  for (size_t i = 0; i < data.size(); ++i) channel[i] = data[i].s[c];
  return channel;
}

}  // namespace

Image frameImage(Context& ctx, const GBuffer& gbuffer, const Buffer<float>& visibility, const Camera& camera,
                 const Light& light, const Bounds& bounds) {
  const uint32_t count = static_cast<uint32_t>(gbuffer.width) * static_cast<uint32_t>(gbuffer.height);
  if (visibility.size() != count)
    throw std::invalid_argument(
        fmt::format("frameImage: {} visibility values for {} pixels", visibility.size(), count));
  // The preview needs only the light's position, axis and cone, not a map: a 1-texel view suffices.
  const LightView shading = fitLightView(light, bounds, 1);
  Buffer<LightViewGpu> shadingGpu(ctx, std::span<const LightViewGpu>(&shading.gpu, 1), CL_MEM_READ_ONLY);
  Buffer<cl_float4> rgba(ctx, count);
  const cl_float4 eye = {{camera.eye.x, camera.eye.y, camera.eye.z, 1.0f}};
  const float cosHalfFov = light.type == LightType::Spot ? std::cos(glm::radians(light.fovDeg) * 0.5f) : -1.0f;
  Kernel shade(ctx, "kernels/shade.cl", "shade_preview", "shade");
  shade.args(gbuffer.position, gbuffer.normal, visibility, count, shadingGpu, eye, cosHalfFov, rgba)
      .launch(count, kShadeGroup);

  Image image(gbuffer.width, gbuffer.height);
  const std::vector<cl_float4> preview = rgba.download(ctx);
  for (int c = 0; c < 4; ++c) image.add(std::string(1, "RGBA"[c]), component(preview, c));
  image.add("visibility.Y", visibility.download(ctx));
  const std::vector<cl_float4> position = gbuffer.position.download(ctx), normal = gbuffer.normal.download(ctx);
  for (int c = 0; c < 3; ++c) image.add(fmt::format("P.{}", "XYZ"[c]), component(position, c));
  for (int c = 0; c < 3; ++c) image.add(fmt::format("N.{}", "XYZ"[c]), component(normal, c));
  image.add("depth.Z", gbuffer.depth.download(ctx));

  auto& attributes = image.attributes();
  attributes["penumbra:device"] =
      fmt::format("{} ({}, {})", ctx.info().name, ctx.info().platformName, ctx.info().driverVersion);
  attributes["penumbra:light"] = light.describe();
  attributes["penumbra:camera"] = fmt::format("{},{},{}:{},{},{}:{}", camera.eye.x, camera.eye.y, camera.eye.z,
                                              camera.target.x, camera.target.y, camera.target.z, camera.fovYDeg);
  return image;
}

}  // namespace penumbra
