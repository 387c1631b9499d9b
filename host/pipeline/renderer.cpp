// One frame: G-buffer, technique (kept across frames while unchanged), preview shading and download into an Image
// (host/pipeline/frame_image.h), with the per-pass device times of everything recorded in between.
#include "host/pipeline/renderer.h"

#include <fmt/format.h>

#include "host/pipeline/frame_image.h"
#include "host/views/views.h"

namespace penumbra {

Renderer::Renderer(Context& ctx, const Scene& scene) : ctx_(ctx), scene_(scene), raster_(ctx) {
  raster_.setScene(scene);
}

Technique& Renderer::techniqueFor(const TechniqueInfo& technique, const Params& params) {
  std::string key = technique.name + ": " + params.describe();
  if (technique_ == nullptr || key != techniqueKey_) {
    technique_.reset();  // release the old instance's buffers before the new one allocates
    technique_ = technique.create(params);
    techniqueKey_ = std::move(key);
  }
  return *technique_;
}

RenderResult Renderer::render(const Camera& camera, const Light& light, const TechniqueInfo& technique,
                              const Params& params) {
  refusePointLight(light, "technique " + technique.name);  // before any work: no technique draws cube maps yet
  Profiler profiler;
  ProfilerScope scope(ctx_, profiler);
  const Bounds bounds = scene_.bounds();
  raster_.drawGBuffer(cameraView(camera, bounds), gbuffer_);
  const size_t count = static_cast<size_t>(camera.width) * static_cast<size_t>(camera.height);
  if (visibility_.size() != count) visibility_.allocate(ctx_, count);

  Technique& shadows = techniqueFor(technique, params);
  const ReceiverBounds receivers =
      reduceReceivers(ctx_, gbuffer_, lightEyeMatrix(light, bounds), light.type == LightType::Spot);
  ShadowFrame frame{ctx_, raster_, scene_, light, camera, gbuffer_, receivers};
  shadows.render(frame, visibility_);

  RenderResult result;
  result.image = frameImage(ctx_, gbuffer_, visibility_, camera, light, bounds);
  shadows.addDebugChannels(ctx_, result.image);
  result.image.flipRows();  // the rasterizer's row 0 is the bottom row
  auto& attributes = result.image.attributes();
  attributes.insert(frame.attributes.begin(), frame.attributes.end());
  attributes["penumbra:technique"] = technique.name;
  attributes["penumbra:parameters"] = params.describe();
  result.passes = profiler.resolve();
  return result;
}

}  // namespace penumbra
