// Preview shading (one kernel launch, stage "shade") and the download of the G-buffer into named channels.
#include "host/pipeline/frame_image.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <initializer_list>
#include <memory>
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

// One output channel and where it lives on the device: a float buffer, or one component of a float4 buffer.
struct ChannelSource {
  std::string name;
  const Buffer<float>* scalar = nullptr;
  const Buffer<cl_float4>* vector = nullptr;
  int component = 0;
};

// The frame's channels in the order of the Image: R, G, B, A, visibility.Y, each light's visibility.<layer>.Y, P.*,
// N.*, depth.Z; those `outputs` leaves out are not there.
std::vector<ChannelSource> channelSources(const GBuffer& gbuffer, std::span<const LightVisibility> lights,
                                          const Buffer<cl_float4>& rgba, FrameOutputs outputs) {
  std::vector<ChannelSource> sources;
  auto components = [&](const Buffer<cl_float4>& buffer, std::initializer_list<const char*> names) {
    int c = 0;
    for (const char* name : names) sources.push_back({name, nullptr, &buffer, c++});
  };
  if (outputs.preview) components(rgba, {"R", "G", "B", "A"});
  sources.push_back({"visibility.Y", lights[0].visibility});
  for (const LightVisibility& lit : lights)
    sources.push_back({lightChannel("visibility", lightLayer(*lit.light)), lit.visibility});
  if (!outputs.surfaces) return sources;
  components(gbuffer.position, {"P.X", "P.Y", "P.Z"});
  components(gbuffer.normal, {"N.X", "N.Y", "N.Z"});
  sources.push_back({"depth.Z", &gbuffer.depth});
  return sources;
}

void recordDownload(Context& ctx, const cl::Event& event, uint64_t bytes) {
  if (ctx.profiler() != nullptr) ctx.profiler()->record("transfer/download", event, bytes);
}

// Elements [first, first + n) of `buffer` into `out`.
template <typename T>
void readRange(Context& ctx, const Buffer<T>& buffer, size_t first, size_t n, T* out) {
  cl::Event event;
  clCheck(ctx.queue().enqueueReadBuffer(buffer.get(), CL_TRUE, first * sizeof(T), n * sizeof(T), out, nullptr, &event),
          "Buffer::download", {}, "transfer");
  recordDownload(ctx, event, n * sizeof(T));
}

// Every source into `image` (rows bottom-up, as on the device). The components of a float4 buffer come down together,
// one band at a time.
void downloadChannels(Context& ctx, std::span<const ChannelSource> sources, Image& image) {
  for (size_t s = 0; s < sources.size();) {
    if (sources[s].scalar != nullptr) {
      image.add(sources[s].name, sources[s].scalar->download(ctx));
      ++s;
      continue;
    }
    size_t end = s;
    while (end < sources.size() && sources[end].vector == sources[s].vector) ++end;
    const Buffer<cl_float4>& buffer = *sources[s].vector;
    const size_t count = buffer.size();
    std::vector<std::vector<float>> channels(end - s, std::vector<float>(count));
    std::vector<cl_float4> band(std::min(count, kDownloadBand));
    for (size_t first = 0; first < count; first += band.size()) {
      const size_t n = std::min(band.size(), count - first);
      readRange(ctx, buffer, first, n, band.data());
      for (size_t c = 0; c < channels.size(); ++c)
        for (size_t i = 0; i < n; ++i) channels[c][first + i] = band[i].s[sources[s + c].component];
    }
    for (size_t c = 0; c < channels.size(); ++c) image.add(sources[s + c].name, std::move(channels[c]));
    s = end;
  }
}

// Rows [first, first + count) of the picture (top-down) from a bottom-up device buffer: device rows
// [height - first - count, height - first), reversed.
template <typename T>
void readRows(Context& ctx, const Buffer<T>& buffer, int width, int height, int first, int count, T* out) {
  const size_t w = static_cast<size_t>(width);
  readRange(ctx, buffer, static_cast<size_t>(height - first - count) * w, w * static_cast<size_t>(count), out);
  for (int y = 0; y < count / 2; ++y)
    std::swap_ranges(out + static_cast<size_t>(y) * w, out + static_cast<size_t>(y + 1) * w,
                     out + static_cast<size_t>(count - 1 - y) * w);
}

// The last band of one float4 buffer, shared by the readers of its components: a writer reads every channel of a
// band before the next band, so each band of the buffer comes down once.
struct VectorBand {
  explicit VectorBand(const Buffer<cl_float4>& source) : buffer(source) {}
  Buffer<cl_float4> buffer;
  int first = -1, count = 0;
  std::vector<cl_float4> rows;
};

std::vector<DeferredChannel> deferredChannels(Context& ctx, std::span<const ChannelSource> sources, int width,
                                              int height) {
  std::vector<DeferredChannel> channels;
  std::vector<std::shared_ptr<VectorBand>> bands;
  for (const ChannelSource& source : sources) {
    if (source.scalar != nullptr) {
      channels.push_back(
          {source.name, [&ctx, buffer = *source.scalar, width, height](int first, int count, std::span<float> out) {
             readRows(ctx, buffer, width, height, first, count, out.data());
           }});
      continue;
    }
    if (bands.empty() || bands.back()->buffer.get() != source.vector->get())
      bands.push_back(std::make_shared<VectorBand>(*source.vector));
    channels.push_back({source.name, [&ctx, band = bands.back(), c = source.component, width, height](
                                         int first, int count, std::span<float> out) {
                          if (band->first != first || band->count != count) {
                            band->rows.resize(static_cast<size_t>(width) * static_cast<size_t>(count));
                            readRows(ctx, band->buffer, width, height, first, count, band->rows.data());
                            band->first = first, band->count = count;
                          }
                          for (size_t i = 0; i < out.size(); ++i) out[i] = band->rows[i].s[c];
                        }});
  }
  return channels;
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
// an inner cone (command-line and scene-file spots keep the preview's own falloff, full up to the cosine of 90% of
// the outer half angle, the fourth term), and glTF's range (0: unlimited).
cl_float4 shadeTerms(const Light& light) {
  const float range = light.type == LightType::Directional ? 0.0f : light.range;
  if (light.type != LightType::Spot) return {{-1.0f, -2.0f, range, 0.0f}};
  const float half = glm::radians(light.fovDeg) * 0.5f;
  const float inner = light.innerFovDeg >= 0.0f ? std::cos(glm::radians(light.innerFovDeg) * 0.5f) : -2.0f;
  return {{std::cos(half), inner, range, std::cos(half * 0.9f)}};
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

Buffer<cl_float4> shadeFrame(Context& ctx, const GBuffer& gbuffer, std::span<const LightVisibility> lights,
                             const Camera& camera, const Bounds& bounds, FrameOutputs outputs) {
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
  return outputs.preview ? shadePreview(ctx, gbuffer, lights, camera, bounds, count) : Buffer<cl_float4>();
}

Image frameHeader(Context& ctx, std::span<const LightVisibility> lights, const Camera& camera, const Bounds& bounds,
                  int width, int height) {
  Image image(width, height);
  const Light& light = *lights[0].light;
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

Image frameImage(Context& ctx, const GBuffer& gbuffer, std::span<const LightVisibility> lights, const Camera& camera,
                 const Bounds& bounds, Buffer<cl_float4>* previewOut, FrameOutputs outputs) {
  Buffer<cl_float4> rgba = shadeFrame(ctx, gbuffer, lights, camera, bounds, outputs);
  Image image = frameHeader(ctx, lights, camera, bounds, gbuffer.width, gbuffer.height);
  downloadChannels(ctx, channelSources(gbuffer, lights, rgba, outputs), image);
  if (previewOut != nullptr) *previewOut = std::move(rgba);
  return image;
}

std::vector<DeferredChannel> frameChannels(Context& ctx, const GBuffer& gbuffer,
                                           std::span<const LightVisibility> lights, const Buffer<cl_float4>& preview,
                                           FrameOutputs outputs) {
  return deferredChannels(ctx, channelSources(gbuffer, lights, preview, outputs), gbuffer.width, gbuffer.height);
}

bool seesSurface(Context& ctx, const GBuffer& gbuffer) {
  const size_t count = gbuffer.depth.size();
  std::vector<float> band(std::min(count, kDownloadBand * 4));
  for (size_t first = 0; first < count; first += band.size()) {
    const size_t n = std::min(band.size(), count - first);
    readRange(ctx, gbuffer.depth, first, n, band.data());
    if (std::any_of(band.begin(), band.begin() + static_cast<std::ptrdiff_t>(n),
                    [](float depth) { return depth != INFINITY; }))
      return true;
  }
  return false;
}

}  // namespace penumbra
