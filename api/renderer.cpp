// pn_renderer: host/pipeline/renderer.h on a pn_context and pn_scene (both retained), with the frame's lights
// resolved as the CLI resolves them (tools/cli/view_options.h): the given ones, else the scene's, else the framing
// light; the camera likewise. Each frame keeps a device copy of every light's visibility.
#include <fmt/format.h>

#include <set>
#include <string>

#include "api/convert.h"
#include "api/guard.h"
#include "api/handles.h"
#include "host/pipeline/frame_lights.h"
#include "host/scene/framing.h"
#include "host/scene/light_names.h"

using penumbra::api::guard;
using penumbra::api::require;

pn_renderer::~pn_renderer() {
  renderer.reset();  // before the context and scene it refers to
  penumbra::api::releaseHandle(scene);
  penumbra::api::releaseHandle(context);
}

namespace {

const penumbra::TechniqueInfo& techniqueOf(const pn_params* own, const pn_params* fallback, size_t light) {
  const pn_params* params = own != nullptr ? own : fallback;
  if (params == nullptr)
    throw std::invalid_argument(
        fmt::format("pn_renderer_render: light {} has no params and the call gives none", light));
  return *params->technique;
}

// No lights given: the scene's (each with a scene file light's own technique, as the CLI does), else the framing
// light, shadowed with `params`.
std::vector<penumbra::FrameLight> frameLights(const pn_scene& sceneHandle, const pn_frame_light* lights, size_t count,
                                              const pn_params* params) {
  const penumbra::Scene& scene = sceneHandle.scene;
  std::vector<penumbra::FrameLight> out;
  if (count == 0) {
    const pn_params& all = *require(params, "pn_renderer_render", "params (the default lights' technique)");
    const std::vector<penumbra::Light> defaults =
        scene.lights.empty() ? std::vector<penumbra::Light>{penumbra::framingLight(scene.bounds())} : scene.lights;
    return penumbra::resolveFrameLights(defaults, *all.technique, all.params, all.given, sceneHandle.spec);
  }
  require(lights, "pn_renderer_render", "lights");
  std::set<std::string> layers;
  for (size_t i = 0; i < count; ++i) {
    const pn_params* own = lights[i].params;
    const penumbra::TechniqueInfo& technique = techniqueOf(own, params, i);
    const std::string name = fmt::format("lights[{}].light", i);
    penumbra::Light light = penumbra::api::fromC(*require(lights[i].light, "pn_renderer_render", name.c_str()),
                                                 "pn_renderer_render", name.c_str());
    if (penumbra::channelSafeName(light.name) != light.name)
      throw std::invalid_argument(fmt::format(
          "pn_renderer_render: light {} name \"{}\" is not channel-safe (ASCII letters, digits, '_', '-', at most {})",
          i, light.name, penumbra::kMaxLightNameLength));
    if (!layers.insert(penumbra::lightLayer(light)).second)
      throw std::invalid_argument(fmt::format(
          "pn_renderer_render: light {} has the layer \"{}\" of an earlier light (give the lights distinct names)", i,
          penumbra::lightLayer(light)));
    out.push_back({std::move(light), &technique, (own != nullptr ? own : params)->params});
  }
  return out;
}

template <class T>
penumbra::Buffer<T> copyOf(penumbra::Context& ctx, const penumbra::Buffer<T>& source) {
  penumbra::Buffer<T> copy(ctx, source.size());
  copy.copyFrom(ctx, source);
  return copy;
}

// The frame's own copies of each light's visibility and of the G-buffer, complete when this returns: the renderer
// overwrites its buffers with the next frame, and a frame is a snapshot. Waits on its own copies only.
void copyDeviceOutputs(penumbra::Context& ctx, const penumbra::Renderer& renderer, size_t lights, pn_frame& frame) {
  for (size_t i = 0; i < lights; ++i) frame.visibility.push_back(copyOf(ctx, renderer.visibility(i)));
  const penumbra::GBuffer& gbuffer = renderer.gbuffer();
  frame.position = copyOf(ctx, gbuffer.position);
  frame.normal = copyOf(ctx, gbuffer.normal);
  frame.depth = copyOf(ctx, gbuffer.depth);
  cl::Event done;
  penumbra::clCheck(ctx.queue().enqueueMarkerWithWaitList(nullptr, &done), "clEnqueueMarkerWithWaitList", {}, "api");
  penumbra::clCheck(done.wait(), "clWaitForEvents", {}, "api");
}

}  // namespace

extern "C" {

pn_status pn_renderer_create(pn_context* context, pn_scene* scene, pn_renderer** renderer) {
  return guard([&] {
    require(renderer, "pn_renderer_create", "renderer");
    require(context, "pn_renderer_create", "context");
    require(scene, "pn_renderer_create", "scene");
    auto created = std::make_unique<pn_renderer>();
    {
      std::lock_guard lock(context->mutex);  // uploads the scene on the context's queue
      created->renderer = std::make_unique<penumbra::Renderer>(*context->context, scene->scene);
    }
    penumbra::api::retainHandle(context, "pn_renderer_create");
    created->context = context;
    penumbra::api::retainHandle(scene, "pn_renderer_create");
    created->scene = scene;
    *renderer = created.release();
  });
}

pn_status pn_renderer_retain(pn_renderer* renderer) {
  return penumbra::api::retainHandle(renderer, "pn_renderer_retain");
}

pn_status pn_renderer_release(pn_renderer* renderer) { return penumbra::api::releaseHandle(renderer); }

pn_status pn_renderer_render(pn_renderer* renderer, const pn_camera* camera, const pn_frame_light* lights,
                             size_t light_count, const pn_params* params, pn_frame** frame) {
  return guard([&] {
    require(frame, "pn_renderer_render", "frame");
    pn_renderer& r = *require(renderer, "pn_renderer_render", "renderer");
    const penumbra::Scene& scene = r.scene->scene;
    // No camera: pn_scene_default_camera's (the scene's first, else the framing view).
    const penumbra::Camera cam = camera != nullptr       ? penumbra::api::fromC(*camera, "pn_renderer_render", "camera")
                                 : scene.cameras.empty() ? penumbra::framingCamera(scene.bounds())
                                                         : scene.cameras.front();
    const std::vector<penumbra::FrameLight> frameLights = ::frameLights(*r.scene, lights, light_count, params);
    // Renderer::render checks every light against its technique before any work.

    auto created = std::make_unique<pn_frame>();
    penumbra::Context& ctx = *r.context->context;
    std::lock_guard lock(r.context->mutex);
    penumbra::RenderResult result = r.renderer->render(cam, frameLights);
    copyDeviceOutputs(ctx, *r.renderer, frameLights.size(), *created);
    created->preview = std::move(result.preview);  // the frame's own: a new buffer every render
    result.image.attributes()["penumbra:scene"] = r.scene->spec;
    created->image = std::move(result.image);
    created->passes = std::move(result.passes);
    for (const penumbra::FrameLight& l : frameLights) created->layers.push_back(penumbra::lightLayer(l.light));
    *frame = created.release();
  });
}

}  // extern "C"
