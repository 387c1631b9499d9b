// pn_renderer: host/pipeline/renderer.h on a pn_context and pn_scene (both retained), with the frame's lights
// resolved as the CLI resolves them (tools/cli/view_options.h): the given ones, else the scene's, else the framing
// light; the camera likewise. Each frame keeps a device copy of every light's visibility.
#include <fmt/format.h>

#include <cstddef>
#include <set>
#include <string>

#include "api/convert.h"
#include "api/guard.h"
#include "api/handles.h"
#include "api/stage_call.h"
#include "host/pipeline/frame_image.h"
#include "host/pipeline/frame_lights.h"
#include "host/scene/framing.h"
#include "host/scene/light_names.h"

using penumbra::api::checkEnum;
using penumbra::api::guard;
using penumbra::api::require;
using penumbra::api::StageCall;

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

// The frame's own copies of the G-buffer and of each light's visibility, or the caller's buffer for a light's
// (`outputs`: none, or one per light, NULL entries the frame's own); the renderer overwrites its buffers with the next
// frame, and a frame is a snapshot. Enqueued only.
void copyDeviceOutputs(penumbra::Context& ctx, const penumbra::Renderer& renderer, size_t lights,
                       const std::vector<penumbra::Buffer<float>>& outputs, bool surfaces, pn_frame& frame) {
  for (size_t i = 0; i < lights; ++i) {
    if (i < outputs.size() && !outputs[i].empty()) {
      frame.visibility.push_back(outputs[i]);
      frame.visibility.back().copyFrom(ctx, renderer.visibility(i));
    } else {
      frame.visibility.push_back(copyOf(ctx, renderer.visibility(i)));
    }
  }
  if (!surfaces) return;
  const penumbra::GBuffer& gbuffer = renderer.gbuffer();
  frame.position = copyOf(ctx, gbuffer.position);
  frame.normal = copyOf(ctx, gbuffer.normal);
  frame.depth = copyOf(ctx, gbuffer.depth);
}

// Waits for everything enqueued so far on the context's queue by waiting on a marker (never clFinish).
void waitForFrame(penumbra::Context& ctx) {
  cl::Event done;
  penumbra::clCheck(ctx.queue().enqueueMarkerWithWaitList(nullptr, &done), "clEnqueueMarkerWithWaitList", {}, "api");
  penumbra::clCheck(done.wait(), "clWaitForEvents", {}, "api");
}

// The caller's visibility outputs (pn_render_options::visibility) as buffers of at least `pixels` floats, checked
// before any work; an empty list when none is given.
std::vector<penumbra::Buffer<float>> visibilityOutputs(StageCall& call, const pn_render_options& o, size_t lights,
                                                       size_t pixels) {
  std::vector<penumbra::Buffer<float>> outputs;
  if (o.visibility_count == 0) return outputs;
  require(o.visibility, "pn_renderer_enqueue", "options->visibility");
  if (o.visibility_count != lights)
    throw std::invalid_argument(fmt::format("pn_renderer_enqueue: options->visibility has {} entries for {} lights",
                                            o.visibility_count, lights));
  for (size_t i = 0; i < lights; ++i) {
    if (o.visibility[i] == nullptr) {
      outputs.emplace_back();
      continue;
    }
    const std::string what = fmt::format("options->visibility[{}]", i);
    penumbra::Buffer<float> out = call.buffer<float>(o.visibility[i], what.c_str());
    if (out.size() < pixels)
      throw std::invalid_argument(
          fmt::format("pn_renderer_enqueue: {} holds {} floats; the frame has {} pixels", what, out.size(), pixels));
    outputs.push_back(penumbra::Buffer<float>::over(out.get(), pixels, call.ctx().context()()));
  }
  return outputs;
}

// One frame of `r` into a new pn_frame: rendered, its device outputs copied, and its host channels either downloaded
// (ALL) or left to be read on request. Holds nothing but what the caller's lock (the StageCall's or its own) covers.
std::unique_ptr<pn_frame> renderFrame(pn_renderer& r, const penumbra::Camera& cam,
                                      const std::vector<penumbra::FrameLight>& frameLights, pn_frame_channels channels,
                                      const std::vector<penumbra::Buffer<float>>& outputs, unsigned outputBits) {
  auto created = std::make_unique<pn_frame>();
  penumbra::Context& ctx = *r.context->context;
  const bool onRequest = channels == PN_FRAME_CHANNELS_ON_REQUEST;
  const penumbra::FrameOutputs kept{(outputBits & PN_FRAME_OUTPUT_PREVIEW_BIT) != 0,
                                    (outputBits & PN_FRAME_OUTPUT_SURFACES_BIT) != 0,
                                    (outputBits & PN_FRAME_OUTPUT_DEBUG_BIT) != 0};
  penumbra::RenderResult result = r.renderer->render(
      cam, frameLights, onRequest ? penumbra::FrameDownload::OnRequest : penumbra::FrameDownload::Image, kept);
  copyDeviceOutputs(ctx, *r.renderer, frameLights.size(), outputs, kept.surfaces, *created);
  created->preview = std::move(result.preview);  // the frame's own: a new buffer every render
  result.image.attributes()["penumbra:scene"] = r.scene->spec;
  created->image = std::move(result.image);
  for (const penumbra::FrameLight& l : frameLights) created->layers.push_back(penumbra::lightLayer(l.light));
  if (onRequest) {
    penumbra::GBuffer copies;
    copies.width = cam.width, copies.height = cam.height;
    copies.position = created->position, copies.normal = created->normal, copies.depth = created->depth;
    std::vector<penumbra::LightVisibility> layers;
    for (size_t i = 0; i < frameLights.size(); ++i) layers.push_back({&frameLights[i].light, &created->visibility[i]});
    created->deferred = penumbra::frameChannels(ctx, copies, layers, created->preview, kept);
    penumbra::api::retainHandle(r.context, "pn_renderer_enqueue");
    created->context = r.context;
    created->pending = std::move(result.profile);
  } else {
    created->passes = std::move(result.passes);
  }
  return created;
}

// The frame's camera: the given one, else pn_scene_default_camera's (the scene's first, else the framing view).
penumbra::Camera frameCamera(const pn_renderer& r, const pn_camera* camera, const char* function) {
  const penumbra::Scene& scene = r.scene->scene;
  return camera != nullptr       ? penumbra::api::fromC(*camera, function, "camera")
         : scene.cameras.empty() ? penumbra::framingCamera(scene.bounds())
                                 : scene.cameras.front();
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
    const penumbra::Camera cam = frameCamera(r, camera, "pn_renderer_render");
    const std::vector<penumbra::FrameLight> frameLights = ::frameLights(*r.scene, lights, light_count, params);
    // Renderer::render checks every light against its technique before any work.
    std::lock_guard lock(r.context->mutex);
    std::unique_ptr<pn_frame> created =
        renderFrame(r, cam, frameLights, PN_FRAME_CHANNELS_ALL, {}, PN_FRAME_OUTPUTS_ALL);
    waitForFrame(*r.context->context);  // the device copies complete when this returns
    *frame = created.release();
  });
}

void pn_render_options_init(pn_render_options* options) {
  if (options == nullptr) return;
  *options = pn_render_options{};
  options->size = sizeof(pn_render_options);
  options->channels = PN_FRAME_CHANNELS_ON_REQUEST;
  options->outputs = PN_FRAME_OUTPUTS_ALL;
}

pn_status pn_renderer_enqueue(pn_renderer* renderer, const pn_camera* camera, const pn_frame_light* lights,
                              size_t light_count, const pn_params* params, const pn_render_options* options,
                              cl_uint num_events_in_wait_list, const cl_event* event_wait_list, cl_event* event,
                              pn_frame** frame) {
  return guard([&] {
    constexpr const char* kFunction = "pn_renderer_enqueue";
    require(frame, kFunction, "frame");
    pn_renderer& r = *require(renderer, kFunction, "renderer");
    pn_render_options defaults;
    pn_render_options_init(&defaults);
    // 0.3's options end before `outputs`; theirs is every output.
    constexpr size_t kFirstSize = offsetof(pn_render_options, outputs);
    const pn_render_options& o = options != nullptr ? penumbra::api::requireSized(options, kFirstSize, kFunction,
                                                                                  "options", "pn_render_options_init")
                                                    : defaults;
    checkEnum(o.channels, 2, kFunction, "options->channels");
    const unsigned outputBits = o.size >= offsetof(pn_render_options, outputs) + sizeof(o.outputs)
                                    ? o.outputs
                                    : static_cast<unsigned>(PN_FRAME_OUTPUTS_ALL);
    if ((outputBits & ~static_cast<unsigned>(PN_FRAME_OUTPUTS_ALL)) != 0)
      throw std::invalid_argument(fmt::format("{}: options->outputs {:#x} has bits beyond PN_FRAME_OUTPUTS_ALL ({:#x})",
                                              kFunction, outputBits, static_cast<unsigned>(PN_FRAME_OUTPUTS_ALL)));
    const penumbra::Camera cam = frameCamera(r, camera, kFunction);
    const std::vector<penumbra::FrameLight> frameLights = ::frameLights(*r.scene, lights, light_count, params);
    StageCall call(r.context, kFunction, num_events_in_wait_list, event_wait_list, event);
    const std::vector<penumbra::Buffer<float>> outputs =
        visibilityOutputs(call, o, frameLights.size(), static_cast<size_t>(cam.width) * cam.height);
    call.begin();
    std::unique_ptr<pn_frame> created = renderFrame(r, cam, frameLights, o.channels, outputs, outputBits);
    call.finish();
    *frame = created.release();
  });
}

}  // extern "C"
