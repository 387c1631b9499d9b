// What the C API's opaque handles hold: each a reference count and the internal objects it stands for. Only api/
// sees these definitions; callers see incomplete types.
#pragma once

#include <atomic>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

#include "host/cl/buffer.h"
#include "host/cl/context.h"
#include "host/cl/profiler.h"
#include "host/io/image.h"
#include "host/io/image_rows.h"
#include "host/pipeline/caller_shade.h"
#include "host/pipeline/renderer.h"
#include "host/scene/scene.h"
#include "host/techniques/technique.h"
#include "penumbra/penumbra.h"

// Every handle starts with one reference (the creator's); api/guard.h's retainHandle / releaseHandle count them.
struct pn_handle_base {
  std::atomic<int> references{1};
};

struct pn_context : pn_handle_base {
  std::unique_ptr<penumbra::Context> context;
  std::mutex mutex;  // serialises every call that enqueues on the context's queue
};

struct pn_scene : pn_handle_base {
  penumbra::Scene scene;
  std::string spec;  // what was loaded: the frames' penumbra:scene
};

struct pn_params : pn_handle_base {
  const penumbra::TechniqueInfo* technique = nullptr;  // in the static registry
  penumbra::Params params;
  penumbra::ParamValues given;  // what pn_params_set set, as text: what a scene light's own technique inherits
  std::string description;  // pn_params_describe's text, refreshed by every change
};

struct pn_renderer : pn_handle_base {
  pn_context* context = nullptr;  // retained: the Renderer keeps a reference to the Context
  pn_scene* scene = nullptr;      // retained: and to the Scene
  std::unique_ptr<penumbra::Renderer> renderer;
  ~pn_renderer();
};

struct pn_shader : pn_handle_base {
  pn_context* context = nullptr;  // retained: the CallerShader keeps a reference to the Context
  std::unique_ptr<penumbra::CallerShader> shader;
  std::map<std::string, std::string> attributes;  // the last successful pn_shade's (pn_shader_attribute)
  ~pn_shader();
};

struct pn_frame : pn_handle_base {
  penumbra::Image image;  // its channels (all of them, or none with channels on request) and its header
  std::vector<std::string> layers;                  // per light
  std::vector<penumbra::Buffer<float>> visibility;  // per light: the frame's own device copy, rows bottom-up
  // The frame's own device copies of the G-buffer and the preview (pn_frame_device_buffer), rows bottom-up.
  penumbra::Buffer<cl_float4> preview, position, normal;
  penumbra::Buffer<float> depth;
  mutable std::vector<penumbra::PassTime> passes;  // resolved from `pending` when first asked for (on request)
  // PN_FRAME_CHANNELS_ON_REQUEST: the channels' readers over the buffers above and the context (retained) whose queue
  // and lock they use; the channels read so far (rows top-down) and the frame's events until the pass times are
  // resolved. `onRequest` guards them and `passes`: a frame is shared between threads.
  pn_context* context = nullptr;
  std::vector<penumbra::DeferredChannel> deferred;
  mutable std::mutex onRequest;
  mutable std::map<std::string, std::vector<float>> fetched;
  mutable std::optional<penumbra::Profiler> pending;
  ~pn_frame();
};
