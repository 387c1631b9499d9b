// A technique on the caller's map and G-buffer (pn_shade): the inputs checked and converted (kernels/caller_inputs.cl),
// the map's view built from the caller's matrices, the technique run as in a Renderer's frame.
#include "host/pipeline/caller_shade.h"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>
#include <utility>

#include "host/cl/kernel.h"
#include "host/techniques/registry.h"
#include "host/techniques/warp.h"
#include "host/views/views.h"
#include "kernels/shared/caller_inputs.h"
#include "kernels/shared/id_buffer.h"

namespace penumbra {

namespace {

constexpr size_t kGroup = 64;
constexpr char kSource[] = "kernels/caller_inputs.cl";
constexpr char kStage[] = "caller";

bool finite(const glm::mat4& m) {
  for (int c = 0; c < 4; ++c)
    for (int r = 0; r < 4; ++r)
      if (!std::isfinite(m[c][r])) return false;
  return true;
}

// z_ndc's two ends in `ndc`'s convention, and a window value's z_ndc.
std::array<float, 2> ndcEnds(NdcDepth ndc) {
  return ndc == NdcDepth::ZeroToOne ? std::array<float, 2>{0.0f, 1.0f} : std::array<float, 2>{-1.0f, 1.0f};
}
float windowOf(NdcDepth ndc, float zNdc) { return ndc == NdcDepth::ZeroToOne ? zNdc : 0.5f * zNdc + 0.5f; }

// The depth reading of a projection: its z and w rows' z_eye terms, and its near and far planes' window values and
// eye depths (which end is near: reversed Z puts it at d = 1).
struct DepthReading {
  CallerDepthGpu gpu{};
  float zNear = 0, zFar = 0;
};

DepthReading depthReading(const glm::mat4& p, DepthStorage storage, NdcDepth ndc, const std::string& what) {
  DepthReading r;
  CallerDepthGpu& g = r.gpu;
  g.storage = storage == DepthStorage::Linear ? CALLER_DEPTH_LINEAR : CALLER_DEPTH_WINDOW;
  g.ndcZeroToOne = ndc == NdcDepth::ZeroToOne ? 1 : 0;
  g.p22 = p[2][2], g.p23 = p[3][2], g.p32 = p[2][3], g.p33 = p[3][3];
  const std::array<float, 2> ends = ndcEnds(ndc);
  std::array<double, 2> depths{};
  for (int e = 0; e < 2; ++e)  // -z_eye = -(p23 - ndc p33) / (ndc p32 - p22), in double
    depths[e] = -(double{g.p23} - ends[e] * double{g.p33}) / (ends[e] * double{g.p32} - double{g.p22});
  const int nearEnd = depths[0] < depths[1] ? 0 : 1, farEnd = 1 - nearEnd;
  r.zNear = static_cast<float>(depths[nearEnd]);
  r.zFar = static_cast<float>(depths[farEnd]);
  if (!std::isfinite(r.zNear) || !std::isfinite(r.zFar) || !(r.zFar > r.zNear))
    throw std::invalid_argument(
        fmt::format("{}: the projection's depth range {:.6g}..{:.6g} is not a finite, non-empty "
                    "range (an infinite far plane cannot normalise the map's depths)",
                    what, depths[nearEnd], depths[farEnd]));
  g.farWindow = windowOf(ndc, ends[farEnd]);
  g.farSign = windowOf(ndc, ends[farEnd]) > windowOf(ndc, ends[nearEnd]) ? 1.0f : -1.0f;
  g.zFar = r.zFar;
  return r;
}

// The map's view from the caller's matrices, as fitLightView would have built it for that window (host/views/views.h);
// `reading` is the projection's depth reading (depthReading), whose planes the caller's depthNear/depthFar may replace.
LightView callerView(const Light& light, const CallerLightMap& map, const DepthReading& reading) {
  const glm::mat4& v = map.view;
  const glm::mat4& p = map.projection;
  if (!finite(v) || !finite(p)) throw std::invalid_argument("light map: the view or projection is not finite");
  for (int c = 0; c < 3; ++c)
    for (int d = 0; d < 3; ++d) {
      const float dot = glm::dot(glm::vec3(v[0][c], v[1][c], v[2][c]), glm::vec3(v[0][d], v[1][d], v[2][d]));
      if (std::abs(dot - (c == d ? 1.0f : 0.0f)) > 1e-4f)
        throw std::invalid_argument(
            "light map: the view matrix is not a rotation and a translation (it scales or "
            "shears: depths would not be world units)");
    }
  if (v[0][3] != 0.0f || v[1][3] != 0.0f || v[2][3] != 0.0f || v[3][3] != 1.0f)
    throw std::invalid_argument("light map: the view matrix's last row is not (0, 0, 0, 1)");
  const bool perspective = p[0][3] == 0.0f && p[1][3] == 0.0f && p[2][3] < 0.0f && p[3][3] == 0.0f;
  const bool orthographic = p[0][3] == 0.0f && p[1][3] == 0.0f && p[2][3] == 0.0f && p[3][3] > 0.0f;
  if ((!perspective && !orthographic) || p[1][0] != 0.0f || p[0][1] != 0.0f || p[0][2] != 0.0f || p[1][2] != 0.0f)
    throw std::invalid_argument(
        "light map: the projection is neither a perspective one (w_c = -k z_eye) nor an "
        "orthographic one (w_c constant) with x_c free of y_eye and y_c of x_eye (no warps)");
  if (light.type == LightType::Spot && !perspective)
    throw std::invalid_argument("light map: a spot light's projection must be a perspective one");
  if (light.type == LightType::Directional && !orthographic)
    throw std::invalid_argument("light map: a directional light's projection must be an orthographic one");
  // The window's width per unit depth (spot) or in world units (directional), along x and y: 2 w / p00.
  const float w = perspective ? -p[2][3] : p[3][3];
  const float widthX = 2.0f * w / p[0][0], widthY = 2.0f * w / p[1][1];
  if (!(widthX > 0.0f) || !(widthY > 0.0f) || std::abs(widthX - widthY) > 1e-3f * widthX)
    throw std::invalid_argument(
        fmt::format("light map: its texels are not square ({:.6g} by {:.6g} per {}); penumbra's "
                    "filters need a square window on a square map",
                    widthX / map.size, widthY / map.size, perspective ? "unit of depth" : "world unit"));
  LightView lv{};
  lv.raster.view = v;
  lv.raster.projection = p;
  lv.raster.width = lv.raster.height = map.size;
  lv.raster.depthMode = DepthMode::kViewZ;
  LightViewGpu& gpu = lv.gpu;
  setLightViewRows(gpu.view, v);
  setLightViewRows(gpu.projection, p);
  const glm::mat4 eyeToWorld = glm::inverse(v);
  const glm::vec3 position(eyeToWorld[3]), axis = -glm::normalize(glm::vec3(eyeToWorld[2]));
  gpu.position = {{position.x, position.y, position.z, 1.0f}};
  gpu.axis = {{axis.x, axis.y, axis.z, 0.0f}};
  gpu.kind = perspective ? LIGHT_KIND_SPOT : LIGHT_KIND_DIRECTIONAL;
  gpu.lightSize = perspective ? light.radius : std::tan(glm::radians(light.angularRadiusDeg));
  gpu.frustumWidth = widthX;
  gpu.texelScale = widthX / static_cast<float>(map.size);
  gpu.width = gpu.height = map.size;
  gpu.warp = LIGHT_WARP_NONE;
  DepthReading depth = reading;
  if (map.depthNear != 0.0f || map.depthFar != 0.0f) {
    if (!std::isfinite(map.depthNear) || !std::isfinite(map.depthFar) || !(map.depthFar > map.depthNear))
      throw std::invalid_argument(fmt::format("light map: depth range {:.6g}..{:.6g} is not a finite, non-empty range",
                                              map.depthNear, map.depthFar));
    if (std::abs(map.depthNear - depth.zNear) > 1e-3f * std::max(std::abs(depth.zNear), depth.zFar - depth.zNear) ||
        std::abs(map.depthFar - depth.zFar) > 1e-3f * std::abs(depth.zFar))
      throw std::invalid_argument(
          fmt::format("light map: depth range {:.6g}..{:.6g} is not the projection's planes "
                      "{:.6g}..{:.6g}",
                      map.depthNear, map.depthFar, depth.zNear, depth.zFar));
    depth.zNear = map.depthNear, depth.zFar = map.depthFar;
  }
  if (perspective && !(depth.zNear > 0.0f))
    throw std::invalid_argument(
        fmt::format("light map: the perspective projection's near plane {:.6g} is not in front "
                    "of the light",
                    depth.zNear));
  gpu.zNear = depth.zNear;
  gpu.zFar = depth.zFar;
  return lv;
}

// The light's frustum between its near and far planes: the stand-in for the scene's bounds.
Bounds frustumBounds(const CallerLightMap& map) {
  const glm::mat4 inverse = glm::inverse(map.projection * map.view);
  const std::array<float, 2> ends = ndcEnds(map.ndc);
  Bounds b;
  for (int i = 0; i < 8; ++i) {
    const glm::vec4 q = inverse * glm::vec4(i & 1 ? 1.0f : -1.0f, i & 2 ? 1.0f : -1.0f, ends[(i >> 2) & 1], 1.0f);
    b.grow(glm::vec3(q) / q.w);
  }
  return b;
}

}  // namespace

std::string callerMapTechniques() {
  std::string names;
  for (const TechniqueInfo& info : techniques())
    if (info.callerMapRefusal.empty()) names += (names.empty() ? "" : ", ") + info.name;
  return names;
}

CallerShader::CallerShader(Context& ctx) : ctx_(ctx), raster_(ctx) {}
CallerShader::~CallerShader() = default;

std::map<std::string, std::string> CallerShader::shade(const TechniqueInfo& technique, const Params& params,
                                                       const Light& light, const CallerLightMap& map,
                                                       const CallerGBuffer& gbuffer,
                                                       const std::optional<Bounds>& sceneBounds,
                                                       CallerImage& visibility,
                                                       const std::function<void()>& beforeCommands) {
  // Everything is checked before the first command.
  if (!technique.callerMapRefusal.empty())
    throw std::invalid_argument(
        fmt::format("technique {} cannot shade from a caller's map: {} (techniques that can: {})", technique.name,
                    technique.callerMapRefusal, callerMapTechniques()));
  if (light.type == LightType::Point)
    throw std::invalid_argument(
        "a point light's shadows are six cube-face maps, each shading the pixels of its own "
        "face; a caller's map is one spot or directional light's");
  if (technique.hasParam("warp") && lispsmEnabled(params))
    throw std::invalid_argument(
        fmt::format("warp lispsm: the caller's map has the caller's own projection (set warp "
                    "to none)"));
  if (technique.hasParam("id-buffer") && params.getInt("id-buffer") != ID_BUFFER_OFF)
    throw std::invalid_argument(
        "id-buffer: a caller's map and G-buffer carry no triangle or object ids (set id-buffer "
        "to off)");
  const auto sizeSpec = std::find_if(technique.params.begin(), technique.params.end(),
                                     [](const ParamSpec& spec) { return spec.name == "map-size"; });
  if (sizeSpec == technique.params.end())
    throw std::logic_error(fmt::format("technique {} shades from a map but has no map-size", technique.name));
  if (map.size < sizeSpec->min || map.size > sizeSpec->max)
    throw std::invalid_argument(fmt::format("light map: {}x{} texels; a map has {}..{} texels per side", map.size,
                                            map.size, sizeSpec->min, sizeSpec->max));
  if (gbuffer.width < 1 || gbuffer.height < 1)
    throw std::invalid_argument(
        fmt::format("G-buffer: {}x{} pixels (width and height must be at least 1)", gbuffer.width, gbuffer.height));
  if (gbuffer.positions.has_value() == gbuffer.depth.has_value())
    throw std::invalid_argument(
        "G-buffer: give either world positions or a depth buffer with the inverse "
        "view-projection, not both or neither");
  const CallerImageGpu mapLayout = imageLayout(map.depth, map.size, map.size, 1, "light map");
  const CallerImageGpu positionLayout =
      gbuffer.positions ? imageLayout(*gbuffer.positions, gbuffer.width, gbuffer.height, 4, "G-buffer positions")
                        : imageLayout(*gbuffer.depth, gbuffer.width, gbuffer.height, 1, "G-buffer depth");
  const std::optional<CallerImageGpu> normalLayout =
      gbuffer.normals
          ? std::optional(imageLayout(*gbuffer.normals, gbuffer.width, gbuffer.height, 4, "G-buffer normals"))
          : std::nullopt;
  const CallerImageGpu visibilityLayout = imageLayout(visibility, gbuffer.width, gbuffer.height, 1, "visibility");
  const DepthReading mapReading = depthReading(map.projection, map.storage, map.ndc, "light map");
  CallerMap callerMap{callerView(light, map, mapReading), {}};
  const CallerDepthGpu& mapDepth = mapReading.gpu;
  std::optional<CallerDepthGpu> cameraDepth;
  if (gbuffer.depth) {
    if (!finite(gbuffer.inverseViewProjection))
      throw std::invalid_argument("G-buffer: the inverse view-projection is not finite");
    CallerDepthGpu d{};
    d.storage = CALLER_DEPTH_WINDOW;
    d.ndcZeroToOne = gbuffer.ndc == NdcDepth::ZeroToOne ? 1 : 0;
    d.farWindow = gbuffer.clearDepth;  // background: the value the depth buffer was cleared to, and beyond
    d.farSign = gbuffer.clearDepth >= 0.5f ? 1.0f : -1.0f;
    cameraDepth = d;
  }

  // The technique's instance for the caller's map size.
  Params shadeParams = params;
  if (shadeParams.isAuto("map-size") || shadeParams.getInt("map-size") != map.size)
    shadeParams.set("map-size", std::to_string(map.size));
  if (technique_ == nullptr || info_ != &technique || !technique_->matches(shadeParams, map.size)) {
    technique_.reset();
    technique_ = technique.create(shadeParams, map.size);
    info_ = &technique;
  }
  if (beforeCommands) beforeCommands();

  // The map's texels, converted when the technique asks for them (renderShadowMap).
  callerMap.writeDepth = [&](Buffer<float>& depth) {
    Kernel kernel(ctx_, kSource, "caller_light_depth", kStage);
    const uint64_t texels = static_cast<uint64_t>(map.size) * map.size;
    kernel.args(map.depth.buffer, mapLayout, mapDepth, depth).moves(texels * 8).launch(texels, kGroup);
  };

  // The G-buffer in penumbra's layout.
  const size_t pixels = static_cast<size_t>(gbuffer.width) * gbuffer.height;
  gbuffer_.width = gbuffer.width, gbuffer_.height = gbuffer.height;
  gbuffer_.position.allocate(ctx_, pixels);
  gbuffer_.normal.allocate(ctx_, pixels);
  gbuffer_.depth.allocate(ctx_, 1);       // read only by LiSPSM's fit and point lights' faces, neither of which applies
  gbuffer_.triangleId.allocate(ctx_, 1);  // read only with an ID buffer
  gbuffer_.objectId.allocate(ctx_, 1);
  if (gbuffer.positions) {
    Kernel kernel(ctx_, kSource, "caller_positions", kStage);
    kernel.args(gbuffer.positions->buffer, positionLayout, gbuffer_.position).moves(pixels * 32).launch(pixels, kGroup);
  } else {
    cl_float4 r[4];
    setLightViewRows(r, gbuffer.inverseViewProjection);
    Kernel kernel(ctx_, kSource, "caller_positions_from_depth", kStage);
    kernel.args(gbuffer.depth->buffer, positionLayout, *cameraDepth, r[0], r[1], r[2], r[3], gbuffer_.position)
        .moves(pixels * 20)
        .launch(pixels, kGroup);
  }
  if (gbuffer.normals) {
    Kernel kernel(ctx_, kSource, "caller_normals", kStage);
    kernel.args(gbuffer.normals->buffer, *normalLayout, gbuffer_.position, gbuffer_.normal)
        .moves(pixels * 32)
        .launch(pixels, kGroup);
  } else {
    Kernel kernel(ctx_, kSource, "caller_derived_normals", kStage);
    kernel
        .args(gbuffer_.position, static_cast<uint32_t>(gbuffer.width), static_cast<uint32_t>(gbuffer.height),
              gbuffer_.normal)
        .moves(pixels * 32)
        .launch(pixels, kGroup);
  }

  // The frame: the caller's light placed where the view says, a scene of no triangles with the caller's bounds.
  Light frameLight = light;
  const LightViewGpu& lv = callerMap.view.gpu;
  frameLight.position = glm::vec3(lv.position.s[0], lv.position.s[1], lv.position.s[2]);
  frameLight.direction = glm::vec3(lv.axis.s[0], lv.axis.s[1], lv.axis.s[2]);
  frameLight.target = frameLight.position + frameLight.direction;
  Scene stand;
  const Bounds bounds = sceneBounds.value_or(frustumBounds(map));
  stand.positions = {bounds.min, bounds.max};
  Camera camera;
  camera.width = gbuffer.width, camera.height = gbuffer.height;
  const ReceiverBounds receivers{};  // empty: nothing is fitted to them
  ShadowFrame frame{ctx_, raster_, stand, frameLight, camera, gbuffer_, receivers};
  frame.callerMap = &callerMap;

  // Visibility straight into the caller's buffer when it is packed rows from the bottom, else through ours.
  if (packedBottomUp(visibilityLayout)) {
    Buffer<float> out = Buffer<float>::over(visibility.buffer.get(), pixels, ctx_.context()());
    technique_->render(frame, out);
  } else {
    visibility_.allocate(ctx_, pixels);
    technique_->render(frame, visibility_);
    const CallerImage own{visibility_};
    copyImage(ctx_, own, imageLayout(own, gbuffer.width, gbuffer.height, 1, "visibility"), visibility,
              visibilityLayout);
  }
  return std::move(frame.attributes);
}

}  // namespace penumbra
