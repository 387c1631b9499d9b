// pn_shader and pn_shade (penumbra/shade.h): host/pipeline/caller_shade.h on the caller's cl_mem buffers, with the
// stage calls' wait list, event and ownership checks (api/stage_call.h).
#include "penumbra/shade.h"

#include <fmt/format.h>

#include <cmath>
#include <glm/gtc/type_ptr.hpp>
#include <optional>
#include <string>

#include "api/guard.h"
#include "api/handles.h"
#include "api/stage_call.h"
#include "host/techniques/registry.h"

using penumbra::api::checkEnum;
using penumbra::api::guard;
using penumbra::api::require;
using penumbra::api::requireSized;
using penumbra::api::requireTexels;
using penumbra::api::StageCall;

pn_shader::~pn_shader() {
  shader.reset();  // before the context it refers to
  penumbra::api::releaseHandle(context);
}

namespace {

constexpr char kShade[] = "pn_shade";

penumbra::NdcDepth ndcDepth(pn_ndc_depth ndc, const char* what) {
  checkEnum(ndc, 2, kShade, what);
  return ndc == PN_NDC_DEPTH_ZERO_TO_ONE ? penumbra::NdcDepth::ZeroToOne : penumbra::NdcDepth::MinusOneToOne;
}

penumbra::Light lightOf(const pn_shade_desc& d) {
  checkEnum(d.light_type, 3, kShade, "desc->light_type");
  penumbra::Light light;
  light.type = d.light_type == PN_LIGHT_SPOT          ? penumbra::LightType::Spot
               : d.light_type == PN_LIGHT_DIRECTIONAL ? penumbra::LightType::Directional
                                                      : penumbra::LightType::Point;
  if (!(d.light_radius >= 0.0f) || !std::isfinite(d.light_radius))
    throw std::invalid_argument(
        fmt::format("{}: desc->light_radius {} is not a finite number >= 0", kShade, d.light_radius));
  if (!(d.light_angular_radius_deg >= 0.0f && d.light_angular_radius_deg < 45.0f))
    throw std::invalid_argument(
        fmt::format("{}: desc->light_angular_radius_deg {} is outside [0, 45)", kShade, d.light_angular_radius_deg));
  light.radius = d.light_radius;
  light.angularRadiusDeg = d.light_angular_radius_deg;
  return light;
}

std::optional<penumbra::Bounds> sceneBounds(const pn_shade_desc& d) {
  if (d.has_scene_bounds == 0) return std::nullopt;
  const glm::vec3 lo = glm::make_vec3(d.scene_min), hi = glm::make_vec3(d.scene_max);
  bool finite = true;
  for (int i = 0; i < 3; ++i) finite = finite && std::isfinite(lo[i]) && std::isfinite(hi[i]);
  if (!finite || !glm::all(glm::lessThanEqual(lo, hi)))
    throw std::invalid_argument(fmt::format("{}: desc->scene_min ({}, {}, {}) and scene_max ({}, {}, {}) are not a box",
                                            kShade, lo.x, lo.y, lo.z, hi.x, hi.y, hi.z));
  return penumbra::Bounds{lo, hi};
}

}  // namespace

extern "C" {

void pn_shade_desc_init(pn_shade_desc* desc) {
  if (desc == nullptr) return;
  *desc = pn_shade_desc{};
  desc->size = sizeof(pn_shade_desc);
  desc->light_type = PN_LIGHT_SPOT;
  desc->light_depth_storage = PN_DEPTH_WINDOW;
  desc->light_ndc_depth = PN_NDC_DEPTH_MINUS_ONE_TO_ONE;
  desc->camera_ndc_depth = PN_NDC_DEPTH_MINUS_ONE_TO_ONE;
  desc->camera_clear_depth = 1.0f;
  for (int i = 0; i < 4; ++i) {
    desc->light_view[i * 5] = 1.0f;
    desc->light_projection[i * 5] = 1.0f;
    desc->camera_inverse_view_projection[i * 5] = 1.0f;
  }
}

pn_status pn_shader_create(pn_context* context, pn_shader** shader) {
  return guard([&] {
    require(shader, "pn_shader_create", "shader");
    require(context, "pn_shader_create", "context");
    auto created = std::make_unique<pn_shader>();
    {
      std::lock_guard lock(context->mutex);
      created->shader = std::make_unique<penumbra::CallerShader>(*context->context);
    }
    penumbra::api::retainHandle(context, "pn_shader_create");
    created->context = context;
    *shader = created.release();
  });
}

pn_status pn_shader_retain(pn_shader* shader) { return penumbra::api::retainHandle(shader, "pn_shader_retain"); }

pn_status pn_shader_release(pn_shader* shader) { return penumbra::api::releaseHandle(shader); }

pn_status pn_shade(pn_shader* shader, const pn_params* params, const pn_shade_desc* desc,
                   cl_uint num_events_in_wait_list, const cl_event* event_wait_list, cl_event* event) {
  return guard([&] {
    pn_shader& s = *require(shader, kShade, "shader");
    const pn_params& p = *require(params, kShade, "params");
    const pn_shade_desc& d = requireSized(desc, sizeof(pn_shade_desc), kShade, "desc", "pn_shade_desc_init");
    const penumbra::Light light = lightOf(d);
    checkEnum(d.light_depth_storage, 2, kShade, "desc->light_depth_storage");
    requireTexels(d.light_map_size, d.light_map_size, kShade, "desc->light_map_size");
    StageCall call(s.context, kShade, num_events_in_wait_list, event_wait_list, event);

    penumbra::CallerLightMap map;
    const std::optional<penumbra::CallerImage> depth =
        call.image(d.light_depth, "desc->light_depth", d.light_map_size, d.light_map_size, 1);
    if (!depth) throw std::invalid_argument("pn_shade: desc->light_depth.memory is NULL");
    map.depth = *depth;
    map.size = static_cast<int>(d.light_map_size);
    map.storage =
        d.light_depth_storage == PN_DEPTH_LINEAR ? penumbra::DepthStorage::Linear : penumbra::DepthStorage::Window;
    map.ndc = ndcDepth(d.light_ndc_depth, "desc->light_ndc_depth");
    map.view = glm::make_mat4(d.light_view);
    map.projection = glm::make_mat4(d.light_projection);
    map.depthNear = d.light_depth_near, map.depthFar = d.light_depth_far;

    penumbra::CallerGBuffer g;
    g.width = static_cast<int>(d.width), g.height = static_cast<int>(d.height);
    requireTexels(d.width, d.height, kShade, "desc->width x height");
    g.positions = call.image(d.positions, "desc->positions", d.width, d.height, 4);
    g.depth = call.image(d.depth, "desc->depth", d.width, d.height, 1);
    g.inverseViewProjection = glm::make_mat4(d.camera_inverse_view_projection);
    g.ndc = ndcDepth(d.camera_ndc_depth, "desc->camera_ndc_depth");
    g.clearDepth = d.camera_clear_depth;
    if (g.depth && !(d.camera_clear_depth == 0.0f || d.camera_clear_depth == 1.0f))
      throw std::invalid_argument(
          fmt::format("pn_shade: desc->camera_clear_depth {} is neither 1 nor 0 (reversed Z)", d.camera_clear_depth));
    g.normals = call.image(d.normals, "desc->normals", d.width, d.height, 4);

    require(d.visibility.memory, kShade, "desc->visibility.memory");
    penumbra::CallerImage visibility;
    visibility.buffer = call.buffer<float>(d.visibility.memory, "desc->visibility");
    visibility.offsetBytes = d.visibility.offset;
    visibility.rowPitchBytes = d.visibility.row_pitch;
    visibility.topDown = d.visibility.top_down != 0;

    const std::optional<penumbra::Bounds> bounds = sceneBounds(d);
    std::map<std::string, std::string> attributes;
    try {
      attributes = s.shader->shade(*p.technique, p.params, light, map, g, bounds, visibility, [&] { call.begin(); });
    } catch (const std::invalid_argument& e) {  // the core's checks, before any command: in the API's terms
      throw std::invalid_argument(fmt::format("{}: {}", kShade, e.what()));
    }
    call.finish();
    s.attributes = std::move(attributes);
  });
}

const char* pn_shader_attribute(const pn_shader* shader, const char* name) {
  if (shader == nullptr || name == nullptr) return nullptr;
  const auto it = shader->attributes.find(name);
  return it == shader->attributes.end() ? nullptr : it->second.c_str();
}

int pn_technique_takes_caller_map(const char* technique, const char** reason) {
  if (reason != nullptr) *reason = "";
  if (technique == nullptr) return 0;
  for (const penumbra::TechniqueInfo& info : penumbra::techniques())
    if (info.name == technique) {
      if (reason != nullptr) *reason = info.callerMapRefusal.c_str();
      return info.callerMapRefusal.empty() ? 1 : 0;
    }
  return 0;
}

}  // extern "C"
