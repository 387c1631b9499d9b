// Planning a draw: validation of the view and projection, the parameter block, grids, launch ranges and the
// work-group table row (raster/constants.h) for a device.
#include "raster/plan.h"

#include <fmt/format.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace penumbra {

glm::mat4 rasterClipMatrix(const RasterView& view) {
  return glm::mat4(glm::dmat4(view.projection) * glm::dmat4(view.view));
}

namespace raster {
namespace {

constexpr size_t kRowDefault[] = {RASTER_WG_ROW_DEFAULT};
constexpr size_t kRowNvidia[] = {RASTER_WG_ROW_NVIDIA};
constexpr size_t kRowPocl[] = {RASTER_WG_ROW_POCL};

bool finite(const glm::mat4& m) {
  for (int c = 0; c < 4; ++c)
    for (int r = 0; r < 4; ++r)
      if (!std::isfinite(m[c][r])) return false;
  return true;
}

// A general projective matrix (kViewZ draws only): -z_eye is row 2 of P^-1 applied to the clip coordinates,
// negated: for clip = P (x, y, z, 1) that row gives z exactly, and clipping interpolates clip coordinates linearly,
// so it holds for clipped vertices too. There is no far plane: z_c / w_c need not be a function of z_eye.
void generalTerms(const glm::mat4& P, RasterViewParams& p) {
  const glm::dmat4 M(P);
  const glm::dmat4 inv = glm::inverse(M);
  bool invertible = glm::determinant(M) != 0;
  for (int c = 0; c < 4; ++c)
    for (int r = 0; r < 4; ++r) invertible = invertible && std::isfinite(inv[c][r]);
  if (!invertible) throw std::invalid_argument("raster view: projection matrix is singular");
  for (int c = 0; c < 4; ++c) p.viewZGeneral[c] = static_cast<float>(-inv[c][2]);
  p.p00 = P[0][0], p.p11 = P[1][1], p.p20 = P[2][0], p.p21 = P[2][1], p.p30 = P[3][0], p.p31 = P[3][1];
  p.p22 = P[2][2], p.p32 = P[3][2], p.p23 = P[2][3], p.p33 = P[3][3];
  p.farViewZ = std::numeric_limits<float>::infinity();
  p.generalProjection = 1;
}

// The projection terms the kernels use; throws unless the matrix has a supported form (rasterizer.h).
void projectionTerms(const glm::mat4& P, DepthMode mode, RasterViewParams& p) {
  const bool separable = P[1][0] == 0 && P[0][1] == 0 && P[0][2] == 0 && P[1][2] == 0 && P[0][3] == 0 && P[1][3] == 0 &&
                         P[0][0] != 0 && P[1][1] != 0;
  const bool perspective = P[2][3] < 0 && P[3][3] == 0 && P[3][2] != 0;
  const bool orthographic = P[2][3] == 0 && P[3][3] > 0 && P[2][2] != 0;
  if (!separable || !(perspective || orthographic)) {
    if (mode == DepthMode::kViewZ) return generalTerms(P, p);
    throw std::invalid_argument(
        "raster view: NDC and distance depth need an OpenGL-style perspective or orthographic projection "
        "(x_c from x and z, y_c from y and z, z_c and w_c from z only); general projective matrices are "
        "supported for linear view depth (DepthMode::kViewZ) only");
  }
  p.p00 = P[0][0], p.p11 = P[1][1], p.p20 = P[2][0], p.p21 = P[2][1], p.p30 = P[3][0], p.p31 = P[3][1];
  p.p22 = P[2][2], p.p32 = P[3][2], p.p23 = P[2][3], p.p33 = P[3][3];
  const double p22 = P[2][2], p32 = P[3][2], p23 = P[2][3], p33 = P[3][3];
  double far;
  if (perspective) {  // w_c = P23 z_eye: v = -w_c / P23; z_ndc = 1 at v = P32 / (P22 - P23)
    p.viewZFromClip[0] = 0, p.viewZFromClip[1] = static_cast<float>(-1.0 / p23), p.viewZFromClip[2] = 0;
    far = p22 == p23 ? std::numeric_limits<double>::infinity() : p32 / (p22 - p23);
  } else {  // z_c = P22 z_eye + P32: v = (P32 - z_c) / P22; z_ndc = 1 at v = (P32 - P33) / P22
    p.viewZFromClip[0] = static_cast<float>(-1.0 / p22), p.viewZFromClip[1] = 0;
    p.viewZFromClip[2] = static_cast<float>(p32 / p22);
    far = (p32 - p33) / p22;
  }
  p.farViewZ = far > 0 || orthographic ? static_cast<float>(far) : std::numeric_limits<float>::infinity();
}

// G = 2^RASTER_GUARD_LOG2 / 2^ceil(log2(size)): a power of two (constants.h).
float guardBand(int size) {
  const int log2Size = std::bit_width(static_cast<unsigned>(size - 1));
  return std::ldexp(1.0f, RASTER_GUARD_LOG2 - log2Size);
}

void viewTerms(const RasterView& view, RasterViewParams& p) {
  const glm::mat4 clip = rasterClipMatrix(view);
  for (int c = 0; c < 4; ++c)
    for (int r = 0; r < 4; ++r) p.clip[c * 4 + r] = clip[c][r];
  const glm::mat4 eyeToWorld(glm::inverse(glm::dmat4(view.view)));
  for (int c = 0; c < 4; ++c)
    for (int r = 0; r < 3; ++r) p.invView[c * 3 + r] = eyeToWorld[c][r];
}

void gridTerms(const RasterView& view, RasterViewParams& p, Plan& plan) {
  Scissor s = view.scissor.value_or(Scissor{0, 0, view.width, view.height});
  p.rectX0 = std::clamp(s.x0, 0, view.width), p.rectX1 = std::clamp(s.x1, 0, view.width);
  p.rectY0 = std::clamp(s.y0, 0, view.height), p.rectY1 = std::clamp(s.y1, 0, view.height);
  if (p.rectX0 >= p.rectX1 || p.rectY0 >= p.rectY1) p.rectX0 = p.rectX1 = p.rectY0 = p.rectY1 = 0;
  const int tile = RASTER_TILE_SIZE, bin = 1 << RASTER_BIN_PIXEL_LOG2;
  p.tilesX = (view.width + tile - 1) / tile, p.tilesY = (view.height + tile - 1) / tile;
  p.binsX = (view.width + bin - 1) / bin, p.binsY = (view.height + bin - 1) / bin;
  plan.bins = static_cast<size_t>(p.binsX) * p.binsY;
  plan.tiles = static_cast<size_t>(p.tilesX) * p.tilesY;
  plan.scissorPixels = static_cast<size_t>(p.rectX1 - p.rectX0) * (p.rectY1 - p.rectY0);
  if (plan.empty()) return;
  p.binX0 = p.rectX0 / bin, p.binY0 = p.rectY0 / bin, p.binsAcross = (p.rectX1 - 1) / bin - p.binX0 + 1;
  p.tileX0 = p.rectX0 / tile, p.tileY0 = p.rectY0 / tile, p.tilesAcross = (p.rectX1 - 1) / tile - p.tileX0 + 1;
  plan.launchedBins = static_cast<size_t>(p.binsAcross) * ((p.rectY1 - 1) / bin - p.binY0 + 1);
  plan.launchedTiles = static_cast<size_t>(p.tilesAcross) * ((p.rectY1 - 1) / tile - p.tileY0 + 1);
}

}  // namespace

WorkGroups workGroupsFor(const DeviceInfo& device) {
  const size_t* row = kRowDefault;
  if (device.layouts == "nvidia") {
    row = kRowNvidia;  // forced (PENUMBRA_LAYOUTS): NVIDIA's row on any device
  } else if (device.layouts.empty()) {
    if (device.vendor.find("NVIDIA") != std::string::npos) row = kRowNvidia;
    if (device.platformName.find("Portable Computing Language") != std::string::npos) row = kRowPocl;
  }
  WorkGroups groups{row[0], row[1], row[2], row[3], row[4], std::max<size_t>(row[5], 1)};
  const size_t limit = std::max<size_t>(device.maxWorkGroupSize, 1);
  groups.setup = std::min(groups.setup, limit), groups.bin = std::min(groups.bin, limit);
  groups.gbuffer = std::min(groups.gbuffer, limit), groups.fine = std::min(groups.fine, limit);
  groups.coarse = std::min(groups.coarse, limit);
  return groups;
}

Plan makePlan(const RasterView& view, uint32_t triangleCount, uint32_t vertexCount, const SceneMaterials& materials) {
  if (view.width < 1 || view.width > RASTER_MAX_VIEWPORT || view.height < 1 || view.height > RASTER_MAX_VIEWPORT)
    throw std::invalid_argument(fmt::format("raster view: size {}x{} outside 1x1 .. {}x{}", view.width, view.height,
                                            RASTER_MAX_VIEWPORT, RASTER_MAX_VIEWPORT));
  if (!finite(view.view) || !finite(view.projection))
    throw std::invalid_argument("raster view: view or projection matrix is not finite");
  const int mode = static_cast<int>(view.depthMode);
  if (mode < RASTER_DEPTH_NDC || mode > RASTER_DEPTH_DISTANCE)
    throw std::invalid_argument(fmt::format("raster view: unknown depth mode {}", mode));
  Plan plan;
  RasterViewParams& p = plan.params;
  projectionTerms(view.projection, view.depthMode, p);
  viewTerms(view, p);
  gridTerms(view, p, plan);
  p.guardX = guardBand(view.width), p.guardY = guardBand(view.height);
  p.width = view.width, p.height = view.height;
  p.depthMode = mode;
  p.cullBackFaces = view.cullBackFaces || (view.cullSingleSided && materials.allSingleSided) ? 1 : 0;
  p.cullSingleSided = !p.cullBackFaces && view.cullSingleSided && materials.anySingleSided ? 1 : 0;
  p.triangleBits = materials.alphaTested || p.cullSingleSided ? 1 : 0;
  p.triangleCount = triangleCount, p.vertexCount = vertexCount;
  p.receiverReach = -1;  // every tile drawn (Rasterizer::draw sets RasterView::receiverReach)
  plan.pixels = static_cast<size_t>(view.width) * view.height;
  if (view.tileMask != nullptr) {
    if (view.tileMask->size() < plan.tiles)
      throw std::invalid_argument(fmt::format("raster view: tile mask of {} entries for a {}x{} grid of tiles",
                                              view.tileMask->size(), p.tilesX, p.tilesY));
    plan.tileMask = view.tileMask;
    p.tileMasked = 1;
  }
  return plan;
}

}  // namespace raster
}  // namespace penumbra
