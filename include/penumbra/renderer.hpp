// penumbra's C++ API: techniques and their parameters (pn_params), the renderer (pn_renderer) and its frames
// (pn_frame).
#pragma once

#include <cstddef>
#include <cstdio>
#include <optional>
#include <string>
#include <type_traits>
#include <vector>

#include "penumbra/context.hpp"
#include "penumbra/error.hpp"
#include "penumbra/renderer.h"
#include "penumbra/scene.hpp"

/// @file
/// penumbra::Params, penumbra::Renderer, penumbra::Frame.

namespace penumbra {
inline namespace v0 {

/// The techniques in the registry, in the CLI's order ("sm", "pcf", "pcss", ...).
inline std::vector<std::string> techniques() {
  std::vector<std::string> names;
  for (size_t i = 0; i < pn_technique_count(); ++i) names.emplace_back(pn_technique_name(i));
  return names;
}

/// A technique and its parameter values (pn_params). Copies share the values: use one per thread.
class Params {
 public:
  /// `technique` with every parameter at its default.
  explicit Params(const std::string& technique) {
    pn_params* params = nullptr;
    detail::check(pn_params_create(technique.c_str(), &params));
    handle_ = Handle(params);
  }
  /// Sets a parameter from text, as the CLI's option ("0.002", "adaptive").
  Params& set(const std::string& name, const std::string& value) {
    detail::check(pn_params_set(get(), name.c_str(), value.c_str()));
    return *this;
  }
  /// Sets a parameter from text.
  Params& set(const std::string& name, const char* value) { return set(name, std::string(value)); }
  /// Sets a number (written with 17 significant digits, so it reads back exactly).
  template <class Number, class = std::enable_if_t<std::is_arithmetic_v<Number>>>
  Params& set(const std::string& name, Number value) {
    char text[32];
    std::snprintf(text, sizeof(text), "%.17g", static_cast<double>(value));
    return set(name, std::string(text));
  }
  /// A number's value, or a choice's index.
  double value(const std::string& name) const {
    double value = 0;
    detail::check(pn_params_get(get(), name.c_str(), &value));
    return value;
  }
  /// The technique's name.
  std::string technique() const { return pn_params_technique(get()); }
  /// "bias=0.002 pcf-radius=2".
  std::string describe() const { return pn_params_describe(get()); }
  /// The C handle (not retained for the caller).
  pn_params* get() const noexcept { return handle_.get(); }

 private:
  using Handle = detail::Handle<pn_params, pn_params_retain, pn_params_release>;
  Handle handle_;
};

/// One light of a frame; without params it takes the render call's.
struct FrameLight {
  Light light;                   ///< The light.
  std::optional<Params> params;  ///< Its own technique and parameters.
};

/// A named pass and its device time.
struct PassTime {
  std::string name;  ///< "shade/pcss_visibility".
  double ms;         ///< Summed device time (0 without queue profiling).
};

/// A rendered frame (pn_frame): immutable; copies share it.
class Frame {
 public:
  /// Takes over one reference to `frame`.
  explicit Frame(pn_frame* frame) noexcept : handle_(frame) {}

  /// Width in pixels.
  int width() const { return pn_frame_width(get()); }
  /// Height in pixels.
  int height() const { return pn_frame_height(get()); }
  /// Channel names, in the frame's order.
  std::vector<std::string> channelNames() const {
    std::vector<std::string> names;
    for (size_t i = 0; i < pn_frame_channel_count(get()); ++i) names.emplace_back(pn_frame_channel_name(get(), i));
    return names;
  }
  /// The channel `name`: width() * height() floats, the top row first, valid while the frame lives.
  const float* channel(const std::string& name) const {
    const float* data = nullptr;
    detail::check(pn_frame_channel(get(), name.c_str(), &data));
    return data;
  }
  /// The EXR layer of each light ("visibility.LAYER.Y").
  std::vector<std::string> lightLayers() const {
    std::vector<std::string> layers;
    for (size_t i = 0; i < pn_frame_light_count(get()); ++i) layers.emplace_back(pn_frame_light_layer(get(), i));
    return layers;
  }
  /// Light `index`'s visibility on the device (width() * height() floats, rows bottom-up), owned by the frame.
  cl_mem visibilityBuffer(size_t index = 0) const {
    cl_mem buffer = nullptr;
    detail::check(pn_frame_visibility_buffer(get(), index, &buffer));
    return buffer;
  }
  /// The preview, G-buffer position, normal or depth on the device (pn_frame_output), owned by the frame.
  cl_mem deviceBuffer(pn_frame_output output) const {
    cl_mem buffer = nullptr;
    detail::check(pn_frame_device_buffer(get(), output, &buffer));
    return buffer;
  }
  /// A provenance attribute ("penumbra:technique", ...), if present.
  std::optional<std::string> attribute(const std::string& name) const {
    const char* value = pn_frame_attribute(get(), name.c_str());
    return value != nullptr ? std::optional<std::string>(value) : std::nullopt;
  }
  /// The named passes and their device times.
  std::vector<PassTime> passes() const {
    std::vector<PassTime> out;
    for (size_t i = 0; i < pn_frame_pass_count(get()); ++i) {
      const char* name = nullptr;
      double ms = 0;
      detail::check(pn_frame_pass(get(), i, &name, &ms));
      out.push_back({name, ms});
    }
    return out;
  }
  /// Every channel and attribute as an OpenEXR file.
  void saveExr(const std::string& path) const { detail::check(pn_frame_save_exr(get(), path.c_str())); }
  /// The C handle (not retained for the caller).
  pn_frame* get() const noexcept { return handle_.get(); }

 private:
  detail::Handle<pn_frame, pn_frame_retain, pn_frame_release> handle_;
};

/// How a frame's host channels are made (pn_frame_channels).
enum class FrameChannels { All = PN_FRAME_CHANNELS_ALL, OnRequest = PN_FRAME_CHANNELS_ON_REQUEST };

/// Renderer::enqueue's settings (pn_render_options; the same defaults).
struct RenderOptions {
  FrameChannels channels = FrameChannels::OnRequest;  ///< All at once, or each read when first asked for.
  std::vector<cl_mem> visibility;  ///< Empty, or one buffer per light (nullptr: the frame's own) to write into.
  /// pn_frame_output_bits: what the frame makes besides each light's visibility.
  unsigned outputs = PN_FRAME_OUTPUTS_ALL;
  /// As the C API takes it; its visibility points into these options.
  pn_render_options toC() const {
    pn_render_options o;
    pn_render_options_init(&o);
    o.channels = static_cast<pn_frame_channels>(channels);
    o.visibility = visibility.empty() ? nullptr : visibility.data();
    o.visibility_count = visibility.size();
    o.outputs = outputs;
    return o;
  }
};

/// Draws frames of one scene on one context (pn_renderer); keeps both alive.
class Renderer {
 public:
  /// A renderer of `scene` on `context`, keeping both alive.
  Renderer(const Context& context, const Scene& scene) {
    pn_renderer* renderer = nullptr;
    detail::check(pn_renderer_create(context.get(), scene.get(), &renderer));
    handle_ = Handle(renderer);
  }
  /// The scene's default camera and lights (as the CLI without --camera and --light), shadowed by `params`.
  Frame render(const Params& params) { return renderC(nullptr, nullptr, 0, params.get()); }
  /// `camera` with the scene's default lights.
  Frame render(const Camera& camera, const Params& params) {
    const pn_camera c = camera.toC();
    return renderC(&c, nullptr, 0, params.get());
  }
  /// One light.
  Frame render(const Camera& camera, const Light& light, const Params& params) {
    return render(camera, std::vector<FrameLight>{{light, std::nullopt}}, &params);
  }
  /// The general form: no camera for the scene's default; several lights, each with its own technique or `params`
  /// (none: the scene's default lights, shadowed by `params`).
  Frame render(const std::optional<Camera>& camera, const std::vector<FrameLight>& lights,
               const Params* params = nullptr) {
    const pn_camera c = camera ? camera->toC() : pn_camera{};
    const CFrameLights cLights(lights);
    return renderC(camera ? &c : nullptr, cLights.data(), cLights.size(), params != nullptr ? params->get() : nullptr);
  }
  /// render()'s general form without waiting for the frame (pn_renderer_enqueue): after `waitFor`, with `event` (may
  /// be null) completing when the frame's device buffers and `options.visibility` are written.
  Frame enqueue(const std::optional<Camera>& camera, const std::vector<FrameLight>& lights, const Params* params,
                const RenderOptions& options, const std::vector<cl_event>& waitFor = {}, cl_event* event = nullptr) {
    const pn_camera c = camera ? camera->toC() : pn_camera{};
    const CFrameLights cLights(lights);
    const pn_render_options o = options.toC();
    pn_frame* frame = nullptr;
    detail::check(pn_renderer_enqueue(
        get(), camera ? &c : nullptr, cLights.data(), cLights.size(), params != nullptr ? params->get() : nullptr, &o,
        static_cast<cl_uint>(waitFor.size()), waitFor.empty() ? nullptr : waitFor.data(), event, &frame));
    return Frame(frame);
  }
  /// The C handle (not retained for the caller).
  pn_renderer* get() const noexcept { return handle_.get(); }

 private:
  // A frame's lights as the C API takes them (pointing into this object).
  class CFrameLights {
   public:
    explicit CFrameLights(const std::vector<FrameLight>& lights) {
      lights_.reserve(lights.size());
      for (const FrameLight& l : lights) lights_.push_back(l.light.toC());
      for (size_t i = 0; i < lights.size(); ++i)
        frame_.push_back({&lights_[i], lights[i].params ? lights[i].params->get() : nullptr});
    }
    const pn_frame_light* data() const { return frame_.empty() ? nullptr : frame_.data(); }
    size_t size() const { return frame_.size(); }

   private:
    std::vector<pn_light> lights_;
    std::vector<pn_frame_light> frame_;
  };

  Frame renderC(const pn_camera* camera, const pn_frame_light* lights, size_t count, const pn_params* params) {
    pn_frame* frame = nullptr;
    detail::check(pn_renderer_render(get(), camera, lights, count, params, &frame));
    return Frame(frame);
  }

  using Handle = detail::Handle<pn_renderer, pn_renderer_retain, pn_renderer_release>;
  Handle handle_;
};

}  // namespace v0
}  // namespace penumbra
