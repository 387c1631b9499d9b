// The moments and blur stages on the caller's buffers (penumbra/stages.h over host/stages/moments.h and blur.h).
#include "api/stage_call.h"
#include "host/stages/blur.h"
#include "host/stages/moments.h"

using penumbra::api::checkEnum;
using penumbra::api::guard;
using penumbra::api::require;
using penumbra::api::requireSized;
using penumbra::api::requireTexels;
using penumbra::api::StageCall;
using penumbra::api::stageShape;

namespace {

penumbra::MomentsConfig momentsConfig(const pn_moments_config* c, const char* function) {
  requireSized(c, sizeof(pn_moments_config), function, "config", "pn_moments_config_init");
  checkEnum(c->kind, 6, function, "moment kind");
  checkEnum(c->storage, 2, function, "moment storage");
  penumbra::MomentsConfig config;
  const penumbra::MomentKind kinds[] = {penumbra::MomentKind::Vsm,   penumbra::MomentKind::Evsm2,
                                        penumbra::MomentKind::Evsm4, penumbra::MomentKind::Lvsm,
                                        penumbra::MomentKind::Msm,   penumbra::MomentKind::Esm};
  config.kind = kinds[c->kind];
  config.depthNear = c->depth_near;
  config.depthFar = c->depth_far;
  config.evsmPositive = c->evsm_positive;
  config.evsmNegative = c->evsm_negative;
  config.esmExponent = c->esm_exponent;
  config.storage =
      c->storage == PN_STORAGE_FLOAT16 ? penumbra::MomentStorage::Float16 : penumbra::MomentStorage::Float32;
  if (c->layer_count > 0) require(c->layers, function, "config->layers");
  for (size_t i = 0; i < c->layer_count; ++i) config.layers.push_back({c->layers[i].p, c->layers[i].q});
  return config;
}

penumbra::BlurConfig blurConfig(const pn_blur_config* c, const char* function) {
  requireSized(c, sizeof(pn_blur_config), function, "blur config", "pn_blur_config_init");
  checkEnum(c->filter, 2, function, "blur filter");
  checkEnum(c->method, 3, function, "blur method");
  penumbra::BlurConfig config;
  config.filter = c->filter == PN_BLUR_BOX ? penumbra::BlurFilter::Box : penumbra::BlurFilter::Gaussian;
  config.sigma = c->sigma;
  config.radius = c->radius;
  const penumbra::BlurMethod methods[] = {penumbra::BlurMethod::Auto, penumbra::BlurMethod::Direct,
                                          penumbra::BlurMethod::RunningSums};
  config.method = methods[c->method];
  return config;
}

penumbra::ImageShape imageShape(const pn_image_shape* s, const char* function) {
  const penumbra::ImageShape shape = stageShape(s, function);
  penumbra::checkShape(shape, function);
  return shape;
}

// The moments of a width x height depth map: one plane of `kind`'s channels, with texels.
penumbra::ImageShape momentShape(uint32_t width, uint32_t height, penumbra::MomentKind kind, const char* function) {
  const penumbra::ImageShape shape{width, height, penumbra::momentChannels(kind)};
  requireTexels(width, height, function);
  penumbra::checkShape(shape, function);
  return shape;
}

}  // namespace

extern "C" {

void pn_moments_config_init(pn_moments_config* config) {
  if (config == nullptr) return;
  const penumbra::MomentsConfig d;
  *config = pn_moments_config{};
  config->size = sizeof(pn_moments_config);
  config->kind = PN_MOMENTS_VSM;
  config->depth_near = d.depthNear, config->depth_far = d.depthFar;
  config->evsm_positive = d.evsmPositive, config->evsm_negative = d.evsmNegative;
  config->storage = PN_STORAGE_FLOAT32;
  config->esm_exponent = d.esmExponent;
}

uint32_t pn_moment_channels(pn_moment_kind kind) {
  switch (kind) {
    case PN_MOMENTS_ESM:
      return 1u;
    case PN_MOMENTS_VSM:
    case PN_MOMENTS_EVSM2:
    case PN_MOMENTS_LVSM:
      return 2u;
    case PN_MOMENTS_EVSM4:
    case PN_MOMENTS_MSM:
      return 4u;
    case PN_MOMENT_KIND_MAX_ENUM:
      break;
  }
  return 0u;  // not a kind
}

pn_status pn_moments(pn_context* context, cl_mem depth, uint32_t width, uint32_t height,
                     const pn_moments_config* config, cl_mem out, cl_uint num_events_in_wait_list,
                     const cl_event* event_wait_list, cl_event* event) {
  return guard([&] {
    StageCall call(context, "pn_moments", num_events_in_wait_list, event_wait_list, event);
    requireTexels(width, height, call.function());
    const penumbra::MomentsConfig moments = momentsConfig(config, call.function());
    const auto in = call.input<float>(depth, "depth", width, height, 1);
    if (moments.storage == penumbra::MomentStorage::Float16) {
      auto target = call.buffer<cl_half>(out, "out");
      call.run([&] { penumbra::computeMoments(call.ctx(), in, width, height, moments, target); });
    } else {
      auto target = call.buffer<float>(out, "out");
      call.run([&] { penumbra::computeMoments(call.ctx(), in, width, height, moments, target); });
    }
  });
}

void pn_blur_config_init(pn_blur_config* config) {
  if (config == nullptr) return;
  const penumbra::BlurConfig d;
  *config = pn_blur_config{sizeof(pn_blur_config), PN_BLUR_GAUSSIAN, d.sigma, d.radius, PN_BLUR_AUTO};
}

pn_status pn_blur(pn_context* context, cl_mem in, cl_mem out, cl_mem scratch, const pn_image_shape* shape,
                  const pn_blur_config* config, cl_uint num_events_in_wait_list, const cl_event* event_wait_list,
                  cl_event* event) {
  return guard([&] {
    StageCall call(context, "pn_blur", num_events_in_wait_list, event_wait_list, event);
    const penumbra::ImageShape s = imageShape(shape, call.function());
    const penumbra::BlurConfig blur = blurConfig(config, call.function());
    const auto source = call.input<float>(in, "in", s.width, s.height, s.channels);
    auto target = call.buffer<float>(out, "out");
    auto temp = call.scratch<float>(scratch, s.count(), "scratch");
    call.run([&] { penumbra::blur(call.ctx(), source, target, temp, s, blur); });
  });
}

pn_status pn_blur_moments(pn_context* context, cl_mem depth, uint32_t width, uint32_t height,
                          const pn_moments_config* moments, const pn_blur_config* blur, cl_mem out, cl_mem scratch,
                          cl_uint num_events_in_wait_list, const cl_event* event_wait_list, cl_event* event) {
  return guard([&] {
    StageCall call(context, "pn_blur_moments", num_events_in_wait_list, event_wait_list, event);
    const penumbra::MomentsConfig m = momentsConfig(moments, call.function());
    const penumbra::BlurConfig b = blurConfig(blur, call.function());
    const penumbra::ImageShape shape = momentShape(width, height, m.kind, call.function());
    const auto in = call.input<float>(depth, "depth", width, height, 1);
    auto temp =
        call.scratch<float>(scratch, penumbra::blurMomentsScratch(call.ctx(), shape, b, m.storage, m.kind), "scratch");
    if (m.storage == penumbra::MomentStorage::Float16) {
      auto target = call.buffer<cl_half>(out, "out");
      call.run([&] { penumbra::blurMoments(call.ctx(), in, m, target, temp, width, height, b); });
    } else {
      auto target = call.buffer<float>(out, "out");
      call.run([&] { penumbra::blurMoments(call.ctx(), in, m, target, temp, width, height, b); });
    }
  });
}

pn_status pn_blur_moments_scratch(pn_context* context, uint32_t width, uint32_t height,
                                  const pn_moments_config* moments, const pn_blur_config* blur, size_t* floats) {
  return guard([&] {
    pn_context& c = *require(context, "pn_blur_moments_scratch", "context");
    const penumbra::MomentsConfig m = momentsConfig(moments, "pn_blur_moments_scratch");
    const penumbra::BlurConfig b = blurConfig(blur, "pn_blur_moments_scratch");
    const penumbra::ImageShape shape = momentShape(width, height, m.kind, "pn_blur_moments_scratch");
    *require(floats, "pn_blur_moments_scratch", "floats") =
        penumbra::blurMomentsScratch(*c.context, shape, b, m.storage, m.kind);
  });
}

pn_status pn_image_copy(pn_context* context, const pn_device_image* src, const pn_device_image* dst, uint32_t width,
                        uint32_t height, uint32_t texel_floats, cl_uint num_events_in_wait_list,
                        const cl_event* event_wait_list, cl_event* event) {
  return guard([&] {
    constexpr const char* kFunction = "pn_image_copy";
    require(src, kFunction, "src");
    require(dst, kFunction, "dst");
    requireTexels(width, height, kFunction);
    if (texel_floats < 1 || texel_floats > 4)
      throw std::invalid_argument(fmt::format("{}: texel_floats {} is not 1..4", kFunction, texel_floats));
    StageCall call(context, kFunction, num_events_in_wait_list, event_wait_list, event);
    const std::optional<penumbra::CallerImage> from = call.image(*src, "src", width, height, texel_floats);
    require(from ? &*from : nullptr, kFunction, "src->memory");
    require(dst->memory, kFunction, "dst->memory");
    penumbra::CallerImage to;
    to.buffer = call.buffer<float>(dst->memory, "dst");
    to.offsetBytes = dst->offset, to.rowPitchBytes = dst->row_pitch, to.topDown = dst->top_down != 0;
    const int w = static_cast<int>(width), h = static_cast<int>(height), c = static_cast<int>(texel_floats);
    const CallerImageGpu fromLayout = penumbra::imageLayout(*from, w, h, c, std::string(kFunction) + ": src");
    const CallerImageGpu toLayout = penumbra::imageLayout(to, w, h, c, std::string(kFunction) + ": dst");
    if (from->buffer.get()() == to.buffer.get()())
      throw std::invalid_argument(fmt::format("{}: src and dst are one buffer (copy through a second one)", kFunction));
    call.run([&] { penumbra::copyImage(call.ctx(), *from, fromLayout, to, toLayout); });
  });
}

}  // extern "C"
