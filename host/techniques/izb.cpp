// `izb`: exact shadows by an irregular z-buffer (kernels/izb.cl). The light grid is a light view fitted like a
// shadow map's (to the receivers the camera sees, or the whole scene), of map-size texels whose 8x8 tiles are the
// cells; the samples are binned into it by a counting sort, the casters drawn over it conservatively by the binned
// rasterizer (Rasterizer::drawTileLists, only the cells that hold samples), and each sample tested exactly against its
// cell's triangles. Under an area light the casters are listed by izb's own kernels in every cell where they can hide
// part of the light, and each sample's N light points (host/techniques/izb_pattern.h) are covered by bitmask lookups
// and exact rays (docs/techniques/izb.md). Memory: 4 bytes per pixel, 8 per sample of a chunk of at most --izb-chunk
// samples (more samples are processed in chunks of whole pixels, each with its own draw), 12 per cell (24 under an
// area light, with 70 per triangle and the pattern's tables), and the grown queues or lists.
#include "kernels/shared/izb.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <stdexcept>

#include "host/cl/kernel.h"
#include "host/scene/camera.h"
#include "host/scene/solids.h"
#include "host/techniques/izb_pattern.h"
#include "host/techniques/registry.h"
#include "host/techniques/shadow_map.h"
#include "host/views/views.h"
#include "raster/caster_test.h"
#include "raster/stages.h"

namespace penumbra {
namespace {

// Work-group size of izb's per-sample and per-cell kernels on every device: its sample kernels spread their groups
// over the launch themselves (IzbFrame::spread), so the smaller groups pixelGroup gives other per-pixel kernels on CPU
// devices buy nothing (builtin:staircase at 640x360: the soft test 13.0 against 13.7 ms with 32).
constexpr size_t kIzbGroup = 64;

// IzbFrame::spread for `groups` work-groups: izb_spread_stride on a CPU device, 1 on other devices.
uint32_t spreadStride(const Context& ctx, size_t groups) {
  if (groups > 0xffffffffu) throw std::logic_error("izb: more work-groups than 32 bits count");
  return ctx.info().isCpu() ? izb_spread_stride(static_cast<uint32_t>(groups)) : 1u;
}

static_assert(IZB_CELL_TEXELS == kRasterTileSize, "izb's cells are the rasterizer's tiles");

// The spot light grid's near plane, relative to its far plane: far closer to the light than the fitted map's (far *
// 1e-4 where the light lies inside the scene's bounds), so casters next to the light are not clipped away. Only the
// grid's x and y are used, which the near plane does not change.
constexpr float kSpotNearOverFar = 1e-7f;

// Perspective `P` (OpenGL convention) with its near plane moved to `zNear`, far kept.
void moveNearPlane(glm::mat4& P, float zNear) {
  const double f = P[3][2] / (P[2][2] + 1.0);  // P22 = -(f + n) / (f - n), P32 = -2 f n / (f - n)
  P[2][2] = static_cast<float>(-(f + zNear) / (f - zNear));
  P[3][2] = static_cast<float>(-2.0 * f * zNear / (f - zNear));
}

// --izb-light-samples N: the side k of its k x k pattern; throws std::invalid_argument unless N = k^2, k in 4..16.
int lightGridOf(int samples) {
  const int k = izb_light_grid_of(samples);
  if (k == 0)
    throw std::invalid_argument(
        fmt::format("--izb-light-samples {}: must be k^2 for k in {}..{} (16, 25, 36, ..., 256)", samples,
                    IZB_MIN_LIGHT_GRID, IZB_MAX_LIGHT_GRID));
  return k;
}

struct IzbSettings {
  int gridSize = 0;  // map-size: the light grid's texels per side
  bool fitReceivers = true;
  int samples = 1;    // per pixel (izb_samples_of_choice)
  size_t chunk = 0;   // izb-chunk
  int lightGrid = 0;  // izb-light-samples = lightGrid^2, under an area light
  static IzbSettings from(const Params& params, int /*mapSize: izb's grid size has no auto*/) {
    return {params.getInt("map-size"), params.getInt("fit") == 1, izb_samples_of_choice(params.getInt("izb-samples")),
            static_cast<size_t>(params.get("izb-chunk")), lightGridOf(params.getInt("izb-light-samples"))};
  }
  bool operator==(const IzbSettings&) const = default;
};

void store3(float* out, const glm::vec3& v) { out[0] = v.x, out[1] = v.y, out[2] = v.z; }

// The area light as the reference samples it (tools/reference/light_samples.cpp) and the listing's reach
// (kernels/izb.cl izb_soft_reach). On a spot grid (spot, cube face) a segment from a receiver sample o to a light point
// l, both in the grid's light eye, meets light depth z at s = (o_z - z) / (o_z - l_z) of its way, where its projection
// has moved from o's by s (l_xy - proj(o) l_z) / z: at most s R sqrt(1 + T^2) / z tangents for |l - c| <= R and
// |proj(o)| <= T, the grid's widest tangent; listReach is R sqrt(1 + T^2) in texels, the kernel bounds s. On a sun
// grid, a direction within alpha of the axis moves (o_z - z) tan(alpha); listReach is tan(alpha) in texels.
void describeLight(IzbFrame& f, const Light& light, const LightView& grid, int lightGrid) {
  f.lightSamples = lightGrid * lightGrid;
  f.lightKind = light.type == LightType::Directional ? IZB_LIGHT_SUN
                : light.type == LightType::Point     ? IZB_LIGHT_SPHERE
                                                     : IZB_LIGHT_DISK;
  const glm::vec3 axis = light.axis();
  const glm::vec3 tangent = glm::normalize(glm::cross(axis, chooseUp(axis)));
  store3(f.lightCentre, light.position);
  store3(f.toLight, -axis);
  store3(f.lightTangent, tangent);
  store3(f.lightBitangent, glm::cross(axis, tangent));
  f.lightRadius = light.radius;
  const float half = 0.5f * glm::radians(light.angularRadiusDeg);
  f.lightOneMinusCos = 2.0f * std::sin(half) * std::sin(half);
  if (grid.gpu.kind == LIGHT_KIND_DIRECTIONAL) {
    f.listReach = std::tan(glm::radians(light.angularRadiusDeg)) / grid.gpu.texelScale;
    return;
  }
  const glm::mat4& P = grid.raster.projection;  // tangent = (ndc + P[2][.]) / P[.][.] for a (cropped) perspective
  float widest = 0.0f;
  for (float x : {-1.0f, 1.0f})
    for (float y : {-1.0f, 1.0f})
      widest = std::max(widest, glm::length(glm::vec2((x + P[2][0]) / P[0][0], (y + P[2][1]) / P[1][1])));
  f.listReach = light.radius * std::sqrt(1.0f + widest * widest) / grid.gpu.texelScale;
}

class IrregularZBuffer final : public TechniqueOf<IzbSettings> {
 public:
  explicit IrregularZBuffer(const IzbSettings& settings) : TechniqueOf(settings), samples_(settings.samples) {}

  void render(ShadowFrame& frame, Buffer<float>& visibility) override {
    Context& ctx = frame.ctx;
    const GBuffer& g = frame.gbuffer;
    const size_t pixels = static_cast<size_t>(g.width) * static_cast<size_t>(g.height);
    LightView grid = gridView(frame);
    gpu_.allocate(ctx, 1, CL_MEM_READ_ONLY);
    gpu_.upload(ctx, std::span<const LightViewGpu>(&grid.gpu, 1));
    const uint32_t cellsX = izb_cells_of(static_cast<uint32_t>(grid.raster.width));
    const uint32_t cellsY = izb_cells_of(static_cast<uint32_t>(grid.raster.height));
    const uint32_t cells = cellsX * cellsY;
    const Light& light = frame.pointLight != nullptr ? *frame.pointLight : frame.light;
    const bool soft = light.isArea();  // a radius of 0 is the exact hard shadow
    const size_t chunk = settings_.chunk;
    const size_t pixelsPerChunk = std::max<size_t>(1, chunk / static_cast<size_t>(samples_));
    const size_t chunkSamples = std::min(pixels, pixelsPerChunk) * static_cast<size_t>(samples_);
    cellOf_.allocate(ctx, chunkSamples);
    sorted_.allocate(ctx, chunkSamples);
    for (Buffer<uint32_t>* b : {&cellCount_, &cellStart_, &cursor_}) b->allocate(ctx, cells);
    blockSums_.allocate(ctx, (cells + IZB_SCAN_BLOCK - 1) / IZB_SCAN_BLOCK);
    occluded_.allocate(ctx, pixels);
    occluded_.fill(ctx, 0u);
    outside_.allocate(ctx, 1);
    outside_.fill(ctx, 0u);
    depthMax_.allocate(ctx, 1);
    if (soft)
      for (Buffer<uint32_t>* b : {&listCount_, &listStart_}) b->allocate(ctx, cells);
    cellDepth_.allocate(ctx, soft ? cells : 1);  // izb_bin writes it only under an area light

    IzbFrame f{};
    const glm::mat4 inverse(glm::inverse(glm::dmat4(rasterClipMatrix(cameraView(frame.camera, frame.scene.bounds())))));
    for (int r = 0; r < 4; ++r)
      for (int c = 0; c < 4; ++c) f.cameraInverse[r * 4 + c] = inverse[c][r];
    f.sceneRadius = frame.scene.boundingRadius();
    f.width = static_cast<uint32_t>(g.width), f.height = static_cast<uint32_t>(g.height);
    f.samples = samples_, f.pattern = izb_pattern_offset(samples_);
    f.cells = cells;

    const raster::SceneBuffers& scene = frame.raster.deviceScene();
    f.alphaTested = scene.materials.alphaTested ? 1u : 0u;
    if (soft) {
      describeLight(f, light, grid, settings_.lightGrid);
      pattern_.prepare(ctx, settings_.lightGrid, f.lightKind == IZB_LIGHT_SUN, f.lightOneMinusCos);
      // 64 bytes per slot of the clusters' lanes (izb_soft_casters), the last cluster's padded.
      selectCasters(ctx, frame, light);
      const uint32_t clusters = izb_cluster_count(casterCount_), slots = clusters * IZB_CLUSTER;
      casters_.allocate(ctx, size_t{16} * std::max<size_t>(slots, 1));
      Kernel casters(ctx, "kernels/izb.cl", "izb_soft_casters", "izb");
      casters.args(scene.positions, scene.triangles, order_, casterCount_, casters_)
          .moves(uint64_t{casterCount_} * 52 + uint64_t{slots} * 64)
          .launch(slots, kIzbGroup);
      clusters_.allocate(ctx, std::max<size_t>(clusters, 1));
      Kernel clusterBalls(ctx, "kernels/izb.cl", "izb_soft_clusters", "izb");
      clusterBalls.args(casters_, casterCount_, clusters_)
          .moves(uint64_t{casterCount_} * 16 + uint64_t{clusters} * 16)
          .launch(clusters, kIzbGroup);
    }
    Kernel bin(ctx, "kernels/izb.cl", "izb_bin", "izb"), scanBlocks(ctx, "kernels/izb.cl", "izb_scan_blocks", "izb");
    Kernel scanSums(ctx, "kernels/izb.cl", "izb_scan_sums", "izb"),
        scanAdd(ctx, "kernels/izb.cl", "izb_scan_add", "izb");
    Kernel scatter(ctx, "kernels/izb.cl", "izb_scatter", "izb"), test(ctx, "kernels/izb.cl", "izb_test", "izb");
    Kernel softTest(ctx, "kernels/izb.cl", "izb_soft_test", "izb");
    uint64_t entries = 0, room = 0;  // room: area lights' list room (Listed)
    int chunks = 0;
    for (size_t begin = 0; begin < pixels; begin += pixelsPerChunk, ++chunks) {
      const size_t count = std::min(pixelsPerChunk, pixels - begin) * static_cast<size_t>(samples_);
      f.pixelBegin = static_cast<uint32_t>(begin), f.sampleCount = static_cast<uint32_t>(count);
      f.spread = spreadStride(ctx, (count + kIzbGroup - 1) / kIzbGroup);
      cellCount_.fill(ctx, 0u);
      cursor_.fill(ctx, 0u);
      if (soft) cellDepth_.fill(ctx, 0u);
      // Bytes floors (Kernel::moves): bin reads each sample's pixel (position, normal, triangle id: 36 B, shared by
      // its samples) and writes its cell (4 B); scatter reads the cell and its start, writes the sorted index; test
      // reads the sorted index and the cell, then data-dependent triangle lists.
      bin.args(g.position, g.normal, g.triangleId, scene.positions, scene.triangles, f, gpu_, cellOf_, cellCount_,
               outside_, cellDepth_)
          .moves(count / static_cast<size_t>(samples_) * 36 + count * 4)
          .launch(count, kIzbGroup);
      scan(scanBlocks, scanSums, scanAdd, cellCount_, cellStart_, cells);
      scatter.args(cellOf_, cellStart_, cursor_, sorted_, f.sampleCount).moves(count * 12).launch(count, kIzbGroup);
      if (soft) {
        const Listed listed = listCasters(ctx, f, cellsX, cellsY, scanBlocks, scanSums, scanAdd);
        entries += listed.entries, room += listed.room;
        softTest
            .args(sorted_, cellOf_, cellStart_, cellCount_, g.position, g.normal, g.triangleId, scene.positions,
                  scene.triangles, f, gpu_, listCount_, listStart_, listEntries_, casters_, clusters_, order_,
                  pattern_.points, pattern_.rotations, pattern_.planePoints, pattern_.masks, scene.alphaIndex,
                  scene.alphaTriangles, scene.alphaMaterials, scene.alphaTexels, occluded_)
            .moves(count * 8)
            .launch(count, kIzbGroup);
        continue;
      }
      grid.raster.tileMask = &cellCount_;
      grid.raster.casterLight = rasterLightOf(light);  // what can shadow no receiver is listed nowhere
      const RasterTileLists lists = frame.raster.drawTileLists(grid.raster);
      entries += lists.entryCount;
      test.args(sorted_, cellOf_, cellStart_, cellCount_, g.position, g.normal, g.triangleId, scene.positions,
                scene.triangles, f, gpu_, *lists.count, *lists.offset, *lists.entries, scene.alphaIndex,
                scene.alphaTriangles, scene.alphaMaterials, scene.alphaTexels, occluded_)
          .moves(count * 8)
          .launch(count, kIzbGroup);
    }
    Kernel resolve(ctx, "kernels/izb.cl", "izb_resolve", "izb");
    const int rays = samples_ * (soft ? f.lightSamples : 1);
    resolve.args(g.position, occluded_, rays, static_cast<uint32_t>(pixels), visibility)
        .moves(pixels * (16 + 4 + 4))
        .launch(pixels, kIzbGroup);
    const uint32_t outside = outside_.download(ctx).front();
    frame.attributes["penumbra:izb"] = fmt::format(
        "{} grid {}x{} texels ({}x{} cells), {} samples per pixel in {} chunk{}, {} {}-cell entries, {} samples "
        "outside the grid (lit)",
        settings_.fitReceivers ? "receivers" : "scene", grid.raster.width, grid.raster.height, cellsX, cellsY, samples_,
        chunks, chunks == 1 ? "" : "s", entries, soft ? "cluster" : "triangle", outside);
    if (soft)
      frame.attributes["penumbra:izb"] += fmt::format(
          "; area light: {} light points per sample ({}x{} stratified, jittered per pixel), casters listed in the "
          "cells where they can hide part of the light (room for {} entries from the {}x{}-cell tiles' lists); {} "
          "casters of {} triangles ({} bounding solids, {} of them facing away from the whole light, and {} that can "
          "shadow no point of the scene, left out)",
          rays / samples_, settings_.lightGrid, settings_.lightGrid, room, IZB_TILE_CELLS, IZB_TILE_CELLS, casterCount_,
          frame.scene.triangles.size(), solids_->triangles, farSides_, castsNothing_);
  }

 private:
  // The light grid: the light's view fitted as a shadow map's, with one texel of margin (a ray origin's offset off its
  // surface and rounding move it less than that); a spot light's near plane moved next to the light.
  LightView gridView(ShadowFrame& frame) const {
    const int size = settings_.gridSize;
    const bool toReceivers = settings_.fitReceivers;
    LightView view =
        fitLightView(frame.light, frame.scene.bounds(), size, toReceivers ? &frame.receivers : nullptr, 1.0f);
    if (view.gpu.kind == LIGHT_KIND_SPOT) moveNearPlane(view.raster.projection, view.gpu.zFar * kSpotNearOverFar);
    return view;
  }

  // start = exclusive scan of count over the cells (kernels/izb.cl izb_scan_*).
  void scan(Kernel& blocks, Kernel& sums, Kernel& add, const Buffer<uint32_t>& count, Buffer<uint32_t>& start,
            uint32_t cells) {
    const size_t groups = (cells + IZB_SCAN_BLOCK - 1) / IZB_SCAN_BLOCK;
    if (groups > IZB_SCAN_BLOCK) throw std::logic_error("izb: more cells than one scan of block sums covers");
    blocks.args(count, start, blockSums_, cells).moves(uint64_t{cells} * 8).launch(groups * IZB_SCAN_WG, IZB_SCAN_WG);
    sums.args(blockSums_, static_cast<uint32_t>(groups)).launch(IZB_SCAN_WG, IZB_SCAN_WG);
    add.args(start, blockSums_, cells).moves(uint64_t{cells} * 8).launch(cells, kIzbGroup);
  }

  // Area lights: every caster listed in the cells holding samples where it can hide part of the light from one of
  // them: the clusters first binned into tiles of IZB_TILE_CELLS^2 cells (kernels/izb.cl izb_soft_tiles, counting then
  // filling, one atomic per cluster and tile), then each cell's own list taken from its tile's in one pass
  // (izb_soft_lists, no atomics) into room for the whole tile (izb_soft_list_bounds), into listCount_, listStart_ and
  // listEntries_ (grown to the bound, never shrunk); returns the entries listed. Listing per cell with an atomic per
  // cluster and cell, counted and then filled, spent 70 % of the lists' time on those atomics on CPUs
  // (docs/techniques/izb.md).
  struct Listed {
    uint64_t entries = 0, room = 0;  // clusters listed in cells, and the room the cells' tiles gave them
  };
  Listed listCasters(Context& ctx, const IzbFrame& f, uint32_t cellsX, uint32_t cellsY, Kernel& scanBlocks,
                     Kernel& scanSums, Kernel& scanAdd) {
    const uint32_t triangles = casterCount_, clusters = izb_cluster_count(triangles), cells = f.cells;
    const uint32_t tiles = izb_tiles_of(cellsX) * izb_tiles_of(cellsY);
    depthMax_.fill(ctx, 0u);
    Kernel depthMax(ctx, "kernels/izb.cl", "izb_depth_max", "izb");
    depthMax.args(cellDepth_, cells, depthMax_)
        .moves(uint64_t{cells} * 4)
        .launch((cells + IZB_DEPTH_MAX_SPAN - 1) / IZB_DEPTH_MAX_SPAN, kIzbGroup);
    Kernel binTiles(ctx, "kernels/izb.cl", "izb_soft_tiles", "izb");
    boxes_.allocate(ctx, std::max<size_t>(clusters, 1));
    tileCount_.allocate(ctx, tiles);
    tileStart_.allocate(ctx, tiles);
    tileCount_.fill(ctx, 0u);
    // Each caster reads its three vertices (36 B) from its record and the cluster writes its box (32 B); the tiles it
    // visits are data-dependent.
    binTiles.args(casters_, triangles, f, gpu_, depthMax_, 0, boxes_, tileCount_, tileStart_, tileEntries_)
        .moves(uint64_t{triangles} * 36 + uint64_t{clusters} * 32)
        .launch(clusters, kIzbGroup);
    const uint64_t tileTotal = totalOf(ctx, tileCount_, "cluster-tile");
    scan(scanBlocks, scanSums, scanAdd, tileCount_, tileStart_, tiles);
    if (tileEntries_.size() < tileTotal) tileEntries_.allocate(ctx, static_cast<size_t>(tileTotal + tileTotal / 4));
    tileCount_.fill(ctx, 0u);  // the same pass again, counting into place
    binTiles.args(casters_, triangles, f, gpu_, depthMax_, 1, boxes_, tileCount_, tileStart_, tileEntries_)
        .moves(uint64_t{clusters} * 32 + tileTotal * 4)
        .launch(clusters, kIzbGroup);
    Kernel bounds(ctx, "kernels/izb.cl", "izb_soft_list_bounds", "izb");
    bounds.args(f, gpu_, cellCount_, tileCount_, listCount_).moves(uint64_t{cells} * 12).launch(cells, kIzbGroup);
    const uint64_t room = totalOf(ctx, listCount_, "cluster-cell");
    scan(scanBlocks, scanSums, scanAdd, listCount_, listStart_, cells);
    if (listEntries_.size() < room) listEntries_.allocate(ctx, static_cast<size_t>(room + room / 4));
    Kernel lists(ctx, "kernels/izb.cl", "izb_soft_lists", "izb");
    // Each cell reads its tile's entries and their clusters' boxes (32 B each), writes its entries and its count.
    lists
        .args(f, gpu_, cellCount_, cellDepth_, boxes_, tileCount_, tileStart_, tileEntries_, listCount_, listStart_,
              listEntries_)
        .moves(uint64_t{cells} * 12 + room * 36)
        .launch(cells, kIzbGroup);
    return {totalOf(ctx, listCount_, "cluster-cell"), room};
  }

  // The sum of `counts` in 64 bits on the host (4 bytes an element), where the device's 32-bit scan would wrap past
  // 2^32.
  static uint64_t totalOf(Context& ctx, const Buffer<uint32_t>& counts, const char* what) {
    uint64_t total = 0;
    for (uint32_t n : counts.download(ctx)) total += n;
    if (total > 0xffffffffu)
      throw std::runtime_error(fmt::format(
          "izb: {} {} entries under the area light exceed 2^32; lower --izb-chunk or --map-size", total, what));
    return total;
  }

  // Area lights: the clusters' triangles in the order of their centroids' Morton codes (30 bits over the scene's
  // bounds, ties by index), so that each cluster's IZB_CLUSTER casters are neighbours and its ball, which every sample
  // of a cell listing it tests first, is small (default.json: the clusters' mean radius 0.49 against 0.75 in the
  // scene's own order). Computed once for the scene the renderer holds, with its solids (the renderer's, else found
  // here).
  void orderCasters(const Scene& scene, const Solids* found) {
    if (orderedScene_ == &scene && orderedTriangles_ == scene.triangles.size()) return;
    const size_t count = scene.triangles.size();
    const Bounds bounds = scene.bounds();
    const glm::vec3 lo = bounds.min, extent = bounds.max - bounds.min;
    std::vector<uint64_t> keys(count);
    for (size_t t = 0; t < count; ++t) {
      const glm::uvec3 v = scene.triangles[t];
      const glm::vec3 centroid = (scene.positions[v.x] + scene.positions[v.y] + scene.positions[v.z]) / 3.0f;
      uint32_t code = 0;
      for (int axis = 0; axis < 3; ++axis) {
        const float u = extent[axis] > 0.0f ? (centroid[axis] - lo[axis]) / extent[axis] : 0.0f;
        const auto q = static_cast<uint32_t>(std::isfinite(u) ? std::clamp(u, 0.0f, 1.0f) * 1023.0f : 0.0f);
        for (int bit = 0; bit < 10; ++bit) code |= ((q >> bit) & 1u) << (3 * bit + axis);
      }
      keys[t] = (uint64_t{code} << 32) | t;
    }
    std::sort(keys.begin(), keys.end());
    mortonOrder_.resize(count);
    for (size_t i = 0; i < count; ++i) mortonOrder_[i] = static_cast<uint32_t>(keys[i]);
    if (found == nullptr) ownSolids_ = findSolids(scene);
    solids_ = found != nullptr ? found : &ownSolids_;
    orderedScene_ = &scene, orderedTriangles_ = count;
    selected_ = false;
  }

  // Area lights: the casters of `light`, the scene's triangles in Morton order (orderCasters) less those of solids that
  // face away from the whole light (host/scene/solids.h: a segment from the light into a solid first crosses one of
  // its triangles that faces some light point, so the others hide nothing more; on scenes/default.json 33 % of the
  // triangles). order_ holds them padded to whole clusters with 0xffffffff, casterCount_ counts them. Made again only
  // when the scene or the light changes.
  void selectCasters(Context& ctx, const ShadowFrame& frame, const Light& light) {
    orderCasters(frame.scene, frame.solids);
    const LightExtent extent = lightExtent(light);
    if (selected_ && extent == selectedLight_) return;
    std::vector<uint32_t> order;
    order.reserve(mortonOrder_.size() + IZB_CLUSTER);
    // Left out: the far sides of solids, and what can shadow no point of the scene (RasterView::casterLight's test).
    const raster::CasterTest casters = frame.raster.casterTest(rasterLightOf(light));
    const Scene& scene = frame.scene;
    farSides_ = castsNothing_ = 0;
    for (uint32_t t : mortonOrder_) {
      const glm::uvec3 v = scene.triangles[t];
      if (facesAwayFromLight(*solids_, t, extent))
        ++farSides_;
      else if (casters.castsNothing(scene.positions[v.x], scene.positions[v.y], scene.positions[v.z]))
        ++castsNothing_;
      else
        order.push_back(t);
    }
    casterCount_ = static_cast<uint32_t>(order.size());
    order.resize(size_t{izb_cluster_count(casterCount_)} * IZB_CLUSTER, 0xffffffffu);
    if (order.empty()) order.push_back(0xffffffffu);
    order_ = Buffer<uint32_t>(ctx, std::span<const uint32_t>(order), CL_MEM_READ_ONLY);
    selectedLight_ = extent, selected_ = true;
  }

  int samples_;
  Buffer<LightViewGpu> gpu_;
  Buffer<uint32_t> cellOf_, sorted_, cellCount_, cellStart_, cursor_, blockSums_, occluded_, outside_;
  Buffer<uint32_t> depthMax_, cellDepth_;   // area lights: the farthest sample's light depth, of the pass and per cell
  Buffer<uint32_t> listCount_, listStart_;  // area lights: casters per cell (izb_soft_lists)
  Buffer<uint32_t> listEntries_;
  Buffer<cl_float8> boxes_;                 // area lights: each cluster's box (izb_soft_tiles)
  Buffer<uint32_t> tileCount_, tileStart_;  // area lights: clusters per tile of cells (izb_soft_tiles)
  Buffer<uint32_t> tileEntries_;
  Buffer<cl_float> casters_;    // area lights: each caster's ball, vertices and plane in its cluster's lanes, 64 bytes
                                // (izb_soft_casters)
  Buffer<cl_float4> clusters_;  // area lights: each IZB_CLUSTER casters' ball (izb_soft_clusters)
  Buffer<uint32_t> order_;      // area lights: the slots' triangles (selectCasters)
  uint32_t casterCount_ = 0;    // area lights: the casters in order_
  uint32_t farSides_ = 0;       // area lights: triangles left out as solids' far sides (facesAwayFromLight)
  uint32_t castsNothing_ = 0;   // and as shadowing no point of the scene (raster::CasterTest)
  const Scene* orderedScene_ = nullptr;
  size_t orderedTriangles_ = 0;
  std::vector<uint32_t> mortonOrder_;  // every triangle, in the order of its centroid's Morton code
  const Solids* solids_ = nullptr;     // the renderer's (ShadowFrame::solids), else ownSolids_
  Solids ownSolids_;
  LightExtent selectedLight_;  // the light order_ was selected for
  bool selected_ = false;
  // Area lights: the light pattern and its bitmask tables on the device, made again only when the pattern or (a sun's)
  // tables change.
  struct PatternGpu {
    std::unique_ptr<IzbLightPattern> host;
    bool sun = false;
    float oneMinusCos = 0.0f;
    bool tables = false;
    Buffer<cl_float2> points, rotations, planePoints;
    Buffer<uint32_t> masks;
    void prepare(Context& ctx, int grid, bool forSun, float sunOneMinusCos) {
      if (!host || host->grid() != grid) {
        host = std::make_unique<IzbLightPattern>(grid);
        tables = false;
        std::vector<cl_float2> p, r;
        for (const glm::vec2& v : host->points()) p.push_back({{v.x, v.y}});
        for (const glm::vec2& v : host->rotations()) r.push_back({{v.x, v.y}});
        points = Buffer<cl_float2>(ctx, std::span<const cl_float2>(p), CL_MEM_READ_ONLY);
        rotations = Buffer<cl_float2>(ctx, std::span<const cl_float2>(r), CL_MEM_READ_ONLY);
      }
      if (tables && sun == forSun && (!sun || oneMinusCos == sunOneMinusCos)) return;
      sun = forSun, oneMinusCos = sunOneMinusCos, tables = true;
      const std::vector<uint32_t> m = host->masks(sun, oneMinusCos, IZB_MASK_MARGIN);
      masks = Buffer<uint32_t>(ctx, std::span<const uint32_t>(m), CL_MEM_READ_ONLY);
      std::vector<cl_float2> q;
      for (const glm::dvec2& v : host->planePoints(sun, oneMinusCos))
        q.push_back({{static_cast<float>(v.x), static_cast<float>(v.y)}});
      planePoints = Buffer<cl_float2>(ctx, std::span<const cl_float2>(q), CL_MEM_READ_ONLY);
    }
  } pattern_;
};

}  // namespace

TechniqueInfo izbTechnique() {
  std::vector<ParamSpec> params = {
      {"map-size", 2048, 16, 8192,
       "Light grid width and height in texels; samples are binned into its 8x8-texel tiles, map-size / 8 cells per "
       "side (finer: shorter triangle lists per sample, more cells per triangle)"},
      {"fit",
       1,
       0,
       1,
       "Light grid fitted to the whole scene, or to the receivers the camera sees",
       {"scene", "receivers"}},
      {"izb-samples",
       0,
       0,
       3,
       "Samples per pixel: 1 (the pixel's G-buffer point), or 4, 8 or 32 points of the pixel's footprint on its "
       "surface's plane, for antialiased hard shadows (visibility = the share that reaches the light)",
       {"1", "4", "8", "32"}},
      {"izb-chunk", IZB_CHUNK_SAMPLES, 64, 1u << 28,
       "Samples binned and tested per pass (8 bytes each on the device); more samples are processed in passes of "
       "whole pixels, each drawing the casters over the cells its samples fill"},
      {"izb-light-samples", 64, 16, 256,
       "Area lights: points of the light each sample's visibility is traced to exactly, a k x k stratified pattern "
       "jittered per pixel (N = k^2, k in 4..16; `penumbra reference --izb-light-samples N` traces the same rays); "
       "a light of radius 0 gets the exact hard shadow"},
      {"cube-guard", 8, 0, 2048,
       "Point lights: each cube face's grid reaches this many texels beyond its 90-degree square on every side"},
  };
  return {"izb",
          "Exact hard shadows: irregular z-buffer, each G-buffer sample tested against the triangles over its cell",
          params,
          makeTechnique<IrregularZBuffer>,
          /*pointLightRefusal=*/{},
          "it tests each pixel's light samples against the scene's triangles themselves, exactly; a depth map has "
          "already lost what it needs"};
}

}  // namespace penumbra
