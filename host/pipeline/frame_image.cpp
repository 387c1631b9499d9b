// Preview shading (one kernel launch, stage "shade") and the download of the G-buffer into named channels.
#include "host/pipeline/frame_image.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <initializer_list>
#include <set>
#include <string>
#include <vector>

#include "host/cl/kernel.h"
#include "host/scene/light_names.h"
#include "host/version.h"
#include "host/views/views.h"

namespace penumbra {
namespace {

constexpr size_t kShadeGroup = 64;
// shade_preview's bandwidth floor: read position and normal (two float4) and visibility, write one float4.
constexpr uint64_t kShadeBytesPerPixel = 2 * 16 + 4 + 16;
// shade_add_direct's: read position, normal, visibility and the running sum, write the sum.
constexpr uint64_t kShadeAddBytesPerPixel = 2 * 16 + 4 + 2 * 4;

// Elements read back per step: the float4 buffers come down through a 1 MiB staging band instead of a whole copy,
// so a frame's host memory is its channels alone (docs/robustness.md: bytes per pixel).
constexpr size_t kDownloadBand = size_t{1} << 16;

// Components 0 .. names.size() - 1 of every element of a float4 buffer as channels `names`, one band at a time.
void addComponents(Context& ctx, const Buffer<cl_float4>& buffer, std::initializer_list<std::string> names,
                   Image& image) {
  const size_t count = buffer.size();
  std::vector<std::vector<float>> channels(names.size(), std::vector<float>(count));
  std::vector<cl_float4> band(std::min(count, kDownloadBand));
  for (size_t first = 0; first < count; first += band.size()) {
    const size_t n = std::min(band.size(), count - first);
    cl::Event event;
    clCheck(ctx.queue().enqueueReadBuffer(buffer.get(), CL_TRUE, first * sizeof(cl_float4), n * sizeof(cl_float4),
                                          band.data(), nullptr, &event),
            "Buffer::download", {}, "transfer");
    if (ctx.profiler() != nullptr) ctx.profiler()->record("transfer/download", event, n * sizeof(cl_float4));
    for (size_t c = 0; c < channels.size(); ++c)
      for (size_t i = 0; i < n; ++i) channels[c][first + i] = band[i].s[c];
  }
  size_t c = 0;
  for (const std::string& name : names) image.add(name, std::move(channels[c++]));
}

// glm's column-major storage of a matrix for column vectors is OpenEXR's row-major storage of the same map for row
// vectors (Imath: p' = p M), so the 16 floats copy as they are.
Matrix44 toExr(const glm::mat4& m) {
  Matrix44 out;
  std::memcpy(out.data(), &m[0][0], sizeof(out));
  return out;
}

}  // namespace

std::string cameraProvenance(const Camera& camera) {
  const bool plain = !camera.orthographic() && camera.up == glm::vec3(0, 1, 0) && camera.clipNear == 0.0f &&
                     !std::isfinite(camera.clipFar);
  if (!plain) return camera.describe();  // glTF cameras: projection kind, up and clip planes too
  return fmt::format("{},{},{}:{},{},{}:{}", camera.eye.x, camera.eye.y, camera.eye.z, camera.target.x, camera.target.y,
                     camera.target.z, camera.fovYDeg);
}

std::vector<float> litMask(std::span<const cl_float4> position, std::span<const cl_float4> normal, const Camera& camera,
                           const Light& light) {
  const bool spot = light.type == LightType::Spot, positional = light.type != LightType::Directional;
  const float cosHalfFov = spot ? std::cos(glm::radians(light.fovDeg) * 0.5f) : -1.0f;
  const glm::vec3 axis = light.axis();
  std::vector<float> mask(position.size(), 0.0f);
  for (size_t i = 0; i < position.size() && i < normal.size(); ++i) {
    if (position[i].s[3] == 0.0f) continue;
    const glm::vec3 p(position[i].s[0], position[i].s[1], position[i].s[2]);
    glm::vec3 n(normal[i].s[0], normal[i].s[1], normal[i].s[2]);
    // Two-sided, like the preview (kernels/shade.cl): the side facing the eye, or an orthographic camera.
    const glm::vec3 toEye = camera.orthographic() ? -camera.forward() : camera.eye - p;
    if (glm::dot(n, toEye) < 0.0f) n = -n;
    const glm::vec3 toLight = positional ? glm::normalize(light.position - p) : -axis;
    const bool faces = glm::dot(n, toLight) > 0.0f;
    const bool inCone = !spot || glm::dot(-toLight, axis) > cosHalfFov;
    mask[i] = faces && inCone ? 1.0f : 0.0f;
  }
  return mask;
}

namespace {

// kernels/shade.cl's light terms: the cosines of the outer and inner half angles, the inner one -2 for a light without
// an inner cone (command-line and scene-file spots keep the preview's own falloff), and glTF's range (0: unlimited).
cl_float4 shadeTerms(const Light& light) {
  const float range = light.type == LightType::Directional ? 0.0f : light.range;
  if (light.type != LightType::Spot) return {{-1.0f, -2.0f, range, 0.0f}};
  const float inner = light.innerFovDeg >= 0.0f ? std::cos(glm::radians(light.innerFovDeg) * 0.5f) : -2.0f;
  return {{std::cos(glm::radians(light.fovDeg) * 0.5f), inner, range, 0.0f}};
}

// The light as kernels/shade.cl reads it: its position, axis and kind. It needs no map: a 1-texel view suffices for
// spot and directional lights; a point light (no single frustum) is its position alone.
LightViewGpu shadeView(const Light& light, const Bounds& bounds) {
  if (light.type != LightType::Point) return fitLightView(light, bounds, 1).gpu;
  LightViewGpu gpu{};
  gpu.kind = LIGHT_KIND_POINT;
  gpu.position = {{light.position.x, light.position.y, light.position.z, 1.0f}};
  gpu.axis = {{0.0f, -1.0f, 0.0f, 0.0f}};
  gpu.width = gpu.height = 1;
  return gpu;
}

// The preview's light-dependent arguments of kernels/shade.cl for one light.
struct ShadeLight {
  LightViewGpu gpu;
  Buffer<LightViewGpu> view;
  cl_float4 terms;
  ShadeLight(Context& ctx, const Light& light, const Bounds& bounds)
      : gpu(shadeView(light, bounds)),
        view(ctx, std::span<const LightViewGpu>(&gpu, 1), CL_MEM_READ_ONLY),
        terms(shadeTerms(light)) {}
};

// One light: shade_preview, as ever. Several: each light's direct term summed (shade_add_direct), then shaded
// with the ambient term once (shade_finish).
Buffer<cl_float4> shadePreview(Context& ctx, const GBuffer& gbuffer, std::span<const LightVisibility> lights,
                               const Camera& camera, const Bounds& bounds, uint32_t count) {
  Buffer<cl_float4> rgba(ctx, count);
  // The point the camera sees from (w = 1), or for an orthographic camera the direction towards it (w = 0).
  const glm::vec4 toEye = camera.orthographic() ? glm::vec4(-camera.forward(), 0.0f) : glm::vec4(camera.eye, 1.0f);
  const cl_float4 eye = {{toEye.x, toEye.y, toEye.z, toEye.w}};
  if (lights.size() == 1) {
    const ShadeLight shading(ctx, *lights[0].light, bounds);
    Kernel shade(ctx, "kernels/shade.cl", "shade_preview", "shade");
    shade.args(gbuffer.position, gbuffer.normal, *lights[0].visibility, count, shading.view, eye, shading.terms, rgba)
        .moves(uint64_t{count} * kShadeBytesPerPixel)
        .launch(count, kShadeGroup);
    return rgba;
  }
  Buffer<float> direct(ctx, count);
  direct.fill(ctx, 0.0f);
  for (const LightVisibility& lit : lights) {
    const ShadeLight shading(ctx, *lit.light, bounds);
    Kernel add(ctx, "kernels/shade.cl", "shade_add_direct", "shade");
    add.args(gbuffer.position, gbuffer.normal, *lit.visibility, count, shading.view, eye, shading.terms, direct)
        .moves(uint64_t{count} * kShadeAddBytesPerPixel)
        .launch(count, kShadeGroup);
  }
  Kernel finish(ctx, "kernels/shade.cl", "shade_finish", "shade");
  finish.args(gbuffer.position, gbuffer.normal, direct, count, eye, rgba)
      .moves(uint64_t{count} * kShadeBytesPerPixel)
      .launch(count, kShadeGroup);
  return rgba;
}

}  // namespace

Image frameImage(Context& ctx, const GBuffer& gbuffer, const Buffer<float>& visibility, const Camera& camera,
                 const Light& light, const Bounds& bounds) {
  const LightVisibility one{&light, &visibility};
  return frameImage(ctx, gbuffer, std::span<const LightVisibility>(&one, 1), camera, bounds);
}

Image frameImage(Context& ctx, const GBuffer& gbuffer, std::span<const LightVisibility> lights, const Camera& camera,
                 const Bounds& bounds, Buffer<cl_float4>* previewOut) {
  const uint32_t count = static_cast<uint32_t>(gbuffer.width) * static_cast<uint32_t>(gbuffer.height);
  if (lights.empty()) throw std::invalid_argument("frameImage: no lights");
  std::set<std::string> layers;
  for (const LightVisibility& lit : lights) {
    if (lit.visibility->size() != count)
      throw std::invalid_argument(
          fmt::format("frameImage: {} visibility values for {} pixels", lit.visibility->size(), count));
    if (!layers.insert(lightLayer(*lit.light)).second)
      throw std::invalid_argument(fmt::format("frameImage: two lights named \"{}\"", lightLayer(*lit.light)));
  }
  Buffer<cl_float4> rgba = shadePreview(ctx, gbuffer, lights, camera, bounds, count);
  const Light& light = *lights[0].light;

  Image image(gbuffer.width, gbuffer.height);
  addComponents(ctx, rgba, {"R", "G", "B", "A"}, image);
  image.add("visibility.Y", lights[0].visibility->download(ctx));
  for (const LightVisibility& lit : lights)
    image.add(lightChannel("visibility", lightLayer(*lit.light)), lit.visibility->download(ctx));
  addComponents(ctx, gbuffer.position, {"P.X", "P.Y", "P.Z"}, image);
  addComponents(ctx, gbuffer.normal, {"N.X", "N.Y", "N.Z"}, image);
  image.add("depth.Z", gbuffer.depth.download(ctx));
  if (previewOut != nullptr) *previewOut = std::move(rgba);

  auto& attributes = image.attributes();
  attributes["penumbra:device"] =
      fmt::format("{} ({}, {})", ctx.info().name, ctx.info().platformName, ctx.info().driverVersion);
  attributes["penumbra:light"] = light.describe();
  if (!light.name.empty()) attributes["penumbra:light-name"] = light.name;  // the scene's (unique) name for it
  if (lights.size() > 1) {
    std::string all;
    for (const LightVisibility& lit : lights)
      all += fmt::format("{}{}={}", all.empty() ? "" : "; ", lightLayer(*lit.light), lit.light->describe());
    attributes["penumbra:lights"] = all;  // every light's layer and form; penumbra:light is the first's
  }
  attributes["penumbra:camera"] = cameraProvenance(camera);
  if (!camera.label().empty()) attributes["penumbra:camera-source"] = camera.label();
  attributes["penumbra:version"] = std::string(version());
  // OpenEXR's standard camera attributes: world -> camera (right-handed, looking down -Z, Y up) and world -> NDC
  // (OpenGL clip space of the G-buffer's own near and far planes; x, y, z in [-1, 1] after the divide, y up).
  const RasterView view = cameraView(camera, bounds);
  image.matrices()["worldToCamera"] = toExr(view.view);
  image.matrices()["worldToNDC"] = toExr(view.projection * view.view);
  return image;
}

}  // namespace penumbra
