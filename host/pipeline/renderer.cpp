// One frame: G-buffer, technique (kept across frames while unchanged), preview shading and download into an Image
// (host/pipeline/frame_image.h), with the per-pass device times of everything recorded in between.
#include "host/pipeline/renderer.h"

#include <fmt/format.h>

#include "host/pipeline/frame_image.h"
#include "host/scene/light_names.h"
#include "host/views/views.h"

namespace penumbra {
namespace {

const ReceiverBounds kNoReceivers{};  // a point light's frame: each cube face reduces its own

}  // namespace

Renderer::Renderer(Context& ctx, const Scene& scene) : ctx_(ctx), scene_(scene), raster_(ctx) {
  raster_.setScene(scene);
}

void Renderer::addDebugChannels(const Light& light, Slot& slot, Image& image) {
  if (light.type != LightType::Point) return slot.technique->addDebugChannels(ctx_, image);
  std::vector<float> faces;
  for (int32_t face : slot.cube.faces().download(ctx_)) faces.push_back(static_cast<float>(face));
  image.add("cubeFace.Y", std::move(faces));
}

Technique& Renderer::techniqueFor(Slot& slot, const TechniqueInfo& technique, const Params& params) {
  std::string key = technique.name + ": " + params.describe();
  if (slot.technique == nullptr || key != slot.key) {
    slot.technique.reset();  // release the old instance's buffers before the new one allocates
    slot.technique = technique.create(params);
    slot.key = std::move(key);
  }
  return *slot.technique;
}

std::map<std::string, std::string> Renderer::shadow(const Camera& camera, const FrameLight& light, Slot& slot) {
  Technique& shadows = techniqueFor(slot, *light.technique, light.params);
  if (light.light.type == LightType::Point) {
    ShadowFrame frame{ctx_, raster_, scene_, light.light, camera, gbuffer_, kNoReceivers};
    slot.cube.render(frame, shadows, light.params, slot.visibility);
    return std::move(frame.attributes);
  }
  const ReceiverBounds receivers = reduceReceivers(ctx_, gbuffer_, lightEyeMatrix(light.light, scene_.bounds()),
                                                   light.light.type == LightType::Spot);
  ShadowFrame frame{ctx_, raster_, scene_, light.light, camera, gbuffer_, receivers};
  shadows.render(frame, slot.visibility);
  return std::move(frame.attributes);
}

RenderResult Renderer::render(const Camera& camera, const Light& light, const TechniqueInfo& technique,
                              const Params& params) {
  return render(camera, {FrameLight{light, &technique, params}});
}

RenderResult Renderer::render(const Camera& camera, const std::vector<FrameLight>& lights) {
  if (lights.empty()) throw std::invalid_argument("Renderer::render: no lights");
  for (const FrameLight& l : lights) refuseUnsupportedLight(l.light, *l.technique);  // before any work
  Profiler profiler;
  ProfilerScope scope(ctx_, profiler);
  const Bounds bounds = scene_.bounds();
  raster_.drawGBuffer(cameraView(camera, bounds), gbuffer_);
  const size_t count = static_cast<size_t>(camera.width) * static_cast<size_t>(camera.height);
  slots_.resize(lights.size());  // fewer lights than last frame free the slots no longer used

  std::vector<LightVisibility> layers;
  std::map<std::string, std::string> firstAttributes;
  for (size_t i = 0; i < lights.size(); ++i) {
    const Light& light = lights[i].light;
    Slot& slot = slots_[i];
    if (slot.visibility.size() != count) slot.visibility.allocate(ctx_, count);
    std::map<std::string, std::string> attributes = shadow(camera, lights[i], slot);
    if (i == 0) firstAttributes = std::move(attributes);
    layers.push_back({&light, &slot.visibility});
  }

  RenderResult result;
  result.image = frameImage(ctx_, gbuffer_, layers, camera, bounds, &result.preview);
  addDebugChannels(lights[0].light, slots_[0], result.image);  // the first light's only
  result.image.flipRows();                                     // the rasterizer's row 0 is the bottom row
  auto& attributes = result.image.attributes();
  attributes.insert(firstAttributes.begin(), firstAttributes.end());
  attributes["penumbra:technique"] = lights[0].technique->name;
  attributes["penumbra:parameters"] = lights[0].params.describe();
  if (lights.size() > 1) {
    std::string all;
    for (const FrameLight& l : lights)
      all += fmt::format("{}{}={} ({})", all.empty() ? "" : "; ", lightLayer(l.light), l.technique->name,
                         l.params.describe());
    attributes["penumbra:light-techniques"] = all;
  }
  result.passes = profiler.resolve();
  return result;
}

}  // namespace penumbra
