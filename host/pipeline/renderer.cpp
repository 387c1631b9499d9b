// One frame: G-buffer, technique (kept across frames while unchanged), preview shading and download into an Image
// or left on the device for a banded write (host/pipeline/frame_image.h), with the per-pass device times of everything
// recorded in between.
#include "host/pipeline/renderer.h"

#include <fmt/format.h>

#include <new>

#include "host/pipeline/frame_check.h"
#include "host/pipeline/frame_image.h"
#include "host/pipeline/map_size.h"
#include "host/pipeline/memory_plan.h"
#include "host/scene/light_names.h"
#include "host/views/views.h"
#include "host/views/raster_scene.h"

namespace penumbra {
namespace {

const ReceiverBounds kNoReceivers{};  // a point light's frame: each cube face reduces its own

// Runs one stage of the frame; running out of host or device memory there is reported with the stage and what the
// plan gave it (a MemoryError), not as a bare std::bad_alloc or CL_MEM_OBJECT_ALLOCATION_FAILURE.
template <class Fn>
auto inStage(const MemoryPlan& plan, const std::string& stage, Fn&& fn) {
  const auto needs = [&] { return fmt::format("the frame's plan: {}", plan.describe()); };
  try {
    return fn();
  } catch (const std::bad_alloc&) {
    throw MemoryError(fmt::format("out of host memory in stage {} ({})", stage, needs()));
  } catch (const ClError& e) {
    const cl_int c = e.code();
    // Not CL_OUT_OF_RESOURCES: it also means a launch asked for more local memory or registers than it may.
    if (c != CL_MEM_OBJECT_ALLOCATION_FAILURE && c != CL_OUT_OF_HOST_MEMORY && c != CL_INVALID_BUFFER_SIZE) throw;
    throw MemoryError(fmt::format("out of device memory in stage {}: {} ({})", stage, e.what(), needs()));
  }
}

// Everything refused before any work: lights a technique cannot shadow, coordinates out of range, a memory plan that
// does not fit. Returns the plan.
MemoryPlan checkedPlan(const Scene& scene, const Camera& camera, const std::vector<FrameLight>& lights,
                       const DeviceInfo& device, std::optional<uint64_t> limit, FrameDownload download,
                       FrameOutputs outputs) {
  if (lights.empty()) throw std::invalid_argument("Renderer::render: no lights");
  std::vector<Light> frameLights;
  std::vector<PlannedLight> planned;
  for (const FrameLight& l : lights) {
    refuseUnsupportedLight(l.light, *l.technique);
    checkMapSizeRange(l.params);
    frameLights.push_back(l.light);
    planned.push_back({l.light.type, l.technique, &l.params});
  }
  checkFrameRange(scene, camera, frameLights);
  MemoryPlan plan = planFrame(camera, planned, download, {scene.triangles.size(), scene.positions.size()}, outputs);
  checkMemoryPlan(plan, device, limit);
  return plan;
}

// The header's record of the techniques: the first light's, and every light's when there are several. Each light's
// per-frame choices (`penumbra:blur-radius`, ...): the first light's under their own names, every further light's as
// `penumbra:LAYER:NAME` (`penumbra:Sun:blur-radius`).
void recordTechniques(const std::vector<FrameLight>& lights,
                      const std::vector<std::map<std::string, std::string>>& lightAttributes, Image& image) {
  auto& attributes = image.attributes();
  for (size_t i = 0; i < lightAttributes.size(); ++i)
    for (const auto& [key, value] : lightAttributes[i]) {
      constexpr std::string_view kPrefix = "penumbra:";
      if (i == 0)
        attributes[key] = value;
      else if (key.starts_with(kPrefix))
        attributes[fmt::format("{}{}:{}", kPrefix, lightLayer(lights[i].light), key.substr(kPrefix.size()))] = value;
    }
  attributes["penumbra:technique"] = lights[0].technique->name;
  attributes["penumbra:parameters"] = lights[0].params.describe();
  if (lights.size() < 2) return;
  std::string all;
  for (const FrameLight& l : lights)
    all += fmt::format("{}{}={} ({})", all.empty() ? "" : "; ", lightLayer(l.light), l.technique->name,
                       l.params.describe());
  attributes["penumbra:light-techniques"] = all;
}

}  // namespace

Renderer::Renderer(Context& ctx, const Scene& scene)
    : ctx_(ctx), scene_(scene), solids_(findSolids(scene)), raster_(ctx) {
  uploadScene(raster_, scene, solids_);
}

void Renderer::addDebugChannels(const Light& light, Slot& slot, Image& image) {
  if (light.type != LightType::Point) return slot.technique->addDebugChannels(ctx_, image);
  std::vector<float> faces;
  for (int32_t face : slot.cube.faces().download(ctx_)) faces.push_back(static_cast<float>(face));
  image.add("cubeFace.Y", std::move(faces));
}

Technique& Renderer::techniqueFor(Slot& slot, const TechniqueInfo& technique, const Params& params, int mapSize) {
  if (slot.technique == nullptr || slot.info != &technique || !slot.technique->matches(params, mapSize)) {
    slot.technique.reset();  // release the old instance's buffers before the new one allocates
    slot.technique = technique.create(params, mapSize);
    slot.info = &technique;
  }
  return *slot.technique;
}

std::map<std::string, std::string> Renderer::shadow(const Camera& camera, const FrameLight& light, Slot& slot) {
  const bool point = light.light.type == LightType::Point;
  const ReceiverBounds receivers = point ? kNoReceivers
                                         : reduceReceivers(ctx_, gbuffer_, lightEyeMatrix(light.light, scene_.bounds()),
                                                           light.light.type == LightType::Spot);
  ShadowFrame frame{ctx_, raster_, scene_, light.light, camera, gbuffer_, receivers};
  frame.solids = &solids_;
  // --map-size auto: the technique instance is the one of this frame's size (host/pipeline/map_size.h).
  const Params& params = light.params;
  const auto& kernelReach = light.technique->kernelReach;
  std::function<double(int)> reach;
  if (kernelReach) reach = [&](int size) { return kernelReach(params, size); };
  const int mapSize = autoMapSize(params) ? sizeMapForFrame(frame, params, slot.probe, reach) : 0;
  Technique& shadows = techniqueFor(slot, *light.technique, params, mapSize);
  if (point)
    slot.cube.render(frame, shadows, mapSize > 0 ? mapSize : params.getInt("map-size"),
                     static_cast<float>(params.get("cube-guard")), slot.visibility);
  else
    shadows.render(frame, slot.visibility);
  return std::move(frame.attributes);
}

RenderResult Renderer::render(const Camera& camera, const Light& light, const TechniqueInfo& technique,
                              const Params& params) {
  return render(camera, {FrameLight{light, &technique, params}});
}

RenderResult Renderer::render(const Camera& camera, const std::vector<FrameLight>& lights, FrameDownload download,
                              FrameOutputs outputs) {
  // Before any work.
  const MemoryPlan plan = checkedPlan(scene_, camera, lights, ctx_.info(), memoryLimit_, download, outputs);
  plannedDeviceBytes_ = plan.deviceBytes();
  Profiler profiler;
  ProfilerScope scope(ctx_, profiler);
  const Bounds bounds = scene_.bounds();
  inStage(plan, "G-buffer", [&] { raster_.drawGBuffer(cameraView(camera, bounds), gbuffer_); });
  const size_t count = static_cast<size_t>(camera.width) * static_cast<size_t>(camera.height);
  slots_.resize(lights.size());  // fewer lights than last frame free the slots no longer used

  std::vector<LightVisibility> layers;
  std::vector<std::map<std::string, std::string>> lightAttributes;
  for (size_t i = 0; i < lights.size(); ++i) {
    const Light& light = lights[i].light;
    Slot& slot = slots_[i];
    std::map<std::string, std::string> attributes =
        inStage(plan, fmt::format("light {} ({})", i, lights[i].technique->name), [&] {
          if (slot.visibility.size() != count) slot.visibility.allocate(ctx_, count);
          return shadow(camera, lights[i], slot);
        });
    lightAttributes.push_back(std::move(attributes));
    layers.push_back({&light, &slot.visibility});
  }

  RenderResult result;
  inStage(plan, "shade and image download", [&] {
    if (download == FrameDownload::Image) {
      result.image = frameImage(ctx_, gbuffer_, layers, camera, bounds, &result.preview, outputs);
    } else {
      if (download == FrameDownload::Deferred) {
        gbuffer_.triangleId = {};  // shading and the outputs need neither
        gbuffer_.objectId = {};
      }
      result.preview = shadeFrame(ctx_, gbuffer_, layers, camera, bounds, outputs);
      result.image = frameHeader(ctx_, layers, camera, bounds, gbuffer_.width, gbuffer_.height);
      result.deferred = frameChannels(ctx_, gbuffer_, layers, result.preview, outputs);
    }
    if (download != FrameDownload::OnRequest && outputs.debug)
      addDebugChannels(lights[0].light, slots_[0], result.image);  // the first light's only
  });
  if (download != FrameDownload::OnRequest) {  // reading the frame back waits for it
    const ImageChannel* alpha = result.image.find("A");
    const std::optional<std::string> warning = alpha != nullptr
                                                   ? emptyFrameWarning(scene_, camera, alpha->data)
                                                   : emptyFrameWarning(scene_, camera, seesSurface(ctx_, gbuffer_));
    if (warning) result.warnings.push_back(*warning);
  }
  for (const FrameLight& light : lights)
    if (const std::optional<std::string> reach = lightReachWarning(scene_, light.light))
      result.warnings.push_back(*reach);
  result.image.flipRows();  // the rasterizer's row 0 is the bottom row (frameChannels' readers flip their own)
  recordTechniques(lights, lightAttributes, result.image);
  if (download == FrameDownload::OnRequest)
    result.profile = profiler;
  else
    result.passes = profiler.resolve();
  return result;
}

}  // namespace penumbra
