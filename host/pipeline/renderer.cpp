// One frame: G-buffer, technique (kept across frames while unchanged), preview shading and download into an Image
// (host/pipeline/frame_image.h), with the per-pass device times of everything recorded in between.
#include "host/pipeline/renderer.h"

#include <fmt/format.h>

#include "host/pipeline/frame_image.h"
#include "host/scene/light_names.h"
#include "host/views/views.h"

namespace penumbra {

Renderer::Renderer(Context& ctx, const Scene& scene) : ctx_(ctx), scene_(scene), raster_(ctx) {
  raster_.setScene(scene);
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

RenderResult Renderer::render(const Camera& camera, const Light& light, const TechniqueInfo& technique,
                              const Params& params) {
  return render(camera, {FrameLight{light, &technique, params}});
}

RenderResult Renderer::render(const Camera& camera, const std::vector<FrameLight>& lights) {
  if (lights.empty()) throw std::invalid_argument("Renderer::render: no lights");
  for (const FrameLight& l : lights)  // before any work: no technique draws cube maps yet
    refusePointLight(l.light, "technique " + l.technique->name);
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
    Technique& shadows = techniqueFor(slot, *lights[i].technique, lights[i].params);
    const ReceiverBounds receivers =
        reduceReceivers(ctx_, gbuffer_, lightEyeMatrix(light, bounds), light.type == LightType::Spot);
    ShadowFrame frame{ctx_, raster_, scene_, light, camera, gbuffer_, receivers};
    shadows.render(frame, slot.visibility);
    if (i == 0) firstAttributes = std::move(frame.attributes);
    layers.push_back({&light, &slot.visibility});
  }

  RenderResult result;
  result.image = frameImage(ctx_, gbuffer_, layers, camera, bounds);
  slots_[0].technique->addDebugChannels(ctx_, result.image);  // the first light's only
  result.image.flipRows();                                    // the rasterizer's row 0 is the bottom row
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
