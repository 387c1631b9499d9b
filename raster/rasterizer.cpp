// The rasterizer's host side: scene upload and validation, queue sizing, and the bounded-memory loop of
// nvdiffrast's RasterImpl::drawTriangles: record every stage, read the counters once, grow whatever overflowed to
// what the run asked for and re-run; a clean error past the hard maximum.
#include "raster/rasterizer.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <span>
#include <stdexcept>
#include <vector>

#include "host/cl/error.h"
#include "raster/alpha_tables.h"
#include "raster/caster_test.h"
#include "raster/plan.h"
#include "raster/solid_sides.h"
#include "raster/stages.h"

namespace penumbra {
namespace {

constexpr int kMaxRounds = 8;  // 3 queues, each grows at most twice (once more when an upstream queue overflowed)

// A fresh target holds `background` from the start only where the draw leaves pixels untouched (a scissor, a tile
// mask, nothing to draw): a draw over the whole viewport writes every pixel itself, in parallel, and filling first
// would touch the fresh pages twice, the first time on one thread (on PoCL 112 ms of sm's first 640x360 frame on
// scenes/default.json went to these fills).
template <class T>
void ensureTarget(Context& ctx, Buffer<T>& buffer, const raster::Plan& plan, const T& background) {
  if (buffer.size() == plan.pixels) return;
  buffer.allocate(ctx, plan.pixels);
  const bool drawsEveryPixel = !plan.empty() && plan.scissorPixels == plan.pixels && plan.tileMask == nullptr;
  if (!drawsEveryPixel) buffer.fill(ctx, background);
}

std::span<const float> floats(std::span<const glm::vec3> v) {
  static_assert(sizeof(glm::vec3) == 3 * sizeof(float));
  return {reinterpret_cast<const float*>(v.data()), v.size() * 3};
}

void validateGeometry(const RasterGeometry& scene) {
  if (scene.triangles.size() >= RASTER_NO_TRIANGLE || scene.positions.size() > RASTER_NO_TRIANGLE)
    throw std::invalid_argument(fmt::format("raster scene: {} triangles over {} vertices exceed 32-bit ids",
                                            scene.triangles.size(), scene.positions.size()));
  if (!scene.normals.empty() && scene.normals.size() != scene.positions.size())
    throw std::invalid_argument(
        fmt::format("raster scene: {} normals for {} positions", scene.normals.size(), scene.positions.size()));
  if (!scene.objectIds.empty() && scene.objectIds.size() != scene.triangles.size())
    throw std::invalid_argument(
        fmt::format("raster scene: {} object ids for {} triangles", scene.objectIds.size(), scene.triangles.size()));
  for (size_t t = 0; t < scene.triangles.size(); ++t)
    for (int k = 0; k < 3; ++k)
      if (scene.triangles[t][k] >= scene.positions.size())
        throw std::invalid_argument(fmt::format("raster scene: triangle {} index {} out of range (vertex count {})", t,
                                                scene.triangles[t][k], scene.positions.size()));
}

// RasterCounters::casterBox decoded and widened to whole tiles (rasterCasterBoxEdge, as fine.cl reads it).
std::array<int, 4> casterTilesBox(const uint32_t (&box)[4]) {
  if (box[2] == 0) return {};
  return {rasterCasterBoxEdge(box[0], 0), rasterCasterBoxEdge(box[1], 1), rasterCasterBoxEdge(box[2], 2),
          rasterCasterBoxEdge(box[3], 3)};
}

}  // namespace

struct Rasterizer::Impl {
  explicit Impl(Context& context) : ctx(context), stages(context) { upload(RasterGeometry{}); }

  void upload(const RasterGeometry& geometry);
  void uploadMaterials(const RasterGeometry& geometry);
  void chooseSolidSides(const RasterView& view, raster::Plan& plan);
  void chooseCasters(const RasterView& view, raster::Plan& plan) const;
  raster::CasterTest casterTest(const RasterLight& light) const { return {light, boundsLo, boundsHi}; }
  void run(const raster::Plan& plan, Buffer<float>& depth, Buffer<uint32_t>& triangleIds,
           Buffer<uint32_t>* emptyTiles = nullptr, Buffer<uint32_t>* casterFree = nullptr);
  void sizeQueues(const raster::Plan& plan);
  bool grow(const char* queue, const char* kernel, uint32_t& capacity, uint64_t requested, size_t recordBytes,
            uint64_t indexLimit);

  Context& ctx;
  raster::Stages stages;
  raster::SceneBuffers scene;
  raster::SolidSides solidSides;
  raster::Queues queues;
  RasterCapacities capacities;
  bool capacitiesChosen = false;  // false: size from the next draw (initial or automatic)
  RasterStats stats;
  glm::vec3 boundsLo{INFINITY}, boundsHi{-INFINITY};  // the finite positions' box (RasterView::casterLight)
  Buffer<float> noDepth;  // the depth and id targets of conservative draws, which write neither
  Buffer<uint32_t> noIds;
  Buffer<uint32_t> noEmptyTiles;  // fine's empty-tile and caster-tile record arguments where the draw keeps none
};

void Rasterizer::Impl::upload(const RasterGeometry& s) {
  validateGeometry(s);
  scene.vertexCount = static_cast<uint32_t>(s.positions.size());
  scene.triangleCount = static_cast<uint32_t>(s.triangles.size());
  scene.positions = Buffer<float>(ctx, floats(s.positions), CL_MEM_READ_ONLY);
  boundsLo = glm::vec3(INFINITY), boundsHi = glm::vec3(-INFINITY);
  for (const glm::vec3& p : s.positions)
    if (std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z))
      boundsLo = glm::min(boundsLo, p), boundsHi = glm::max(boundsHi, p);
  std::vector<glm::vec3> zeroNormals;
  if (s.normals.empty()) zeroNormals.assign(s.positions.size(), glm::vec3(0));  // G-buffer: geometric normals
  scene.normals = Buffer<float>(ctx, floats(s.normals.empty() ? zeroNormals : s.normals), CL_MEM_READ_ONLY);
  static_assert(sizeof(glm::uvec3) == 3 * sizeof(uint32_t));
  scene.triangles = Buffer<uint32_t>(
      ctx, std::span<const uint32_t>(reinterpret_cast<const uint32_t*>(s.triangles.data()), s.triangles.size() * 3),
      CL_MEM_READ_ONLY);
  std::vector<uint32_t> objectIds(s.objectIds.begin(), s.objectIds.end());
  objectIds.resize(s.triangles.size(), 0);
  scene.objectIds = Buffer<uint32_t>(ctx, std::span<const uint32_t>(objectIds), CL_MEM_READ_ONLY);
  uploadMaterials(s);
  solidSides.set(s);
  static constexpr uint8_t kNoCodes = RASTER_CULL_NONE;
  scene.solidSides = Buffer<uint8_t>(ctx, std::span<const uint8_t>(&kNoCodes, 1), CL_MEM_READ_ONLY);
  capacitiesChosen = false;
}

// A draw that may drop the far sides of solids gets their codes for its centre, uploaded when they change.
void Rasterizer::Impl::chooseSolidSides(const RasterView& view, raster::Plan& plan) {
  if (!view.cullSolidsFarSides || solidSides.empty() || plan.params.generalProjection || plan.empty()) return;
  const raster::SolidSides::Codes codes = solidSides.codesFor(view);
  if (codes.codes == nullptr) return;
  if (codes.changed) scene.solidSides = Buffer<uint8_t>(ctx, std::span<const uint8_t>(*codes.codes), CL_MEM_READ_ONLY);
  plan.params.solidSides = 1;
}

// A shadow-map draw for a light (RasterView::casterLight): the light and the geometry's box for setup's caster test.
void Rasterizer::Impl::chooseCasters(const RasterView& view, raster::Plan& plan) const {
  if (view.casterLight && !plan.empty()) casterTest(*view.casterLight).describe(plan.params);
}

// The alpha and sidedness tables (raster/alpha_tables.h); one placeholder entry each where a scene needs none.
void Rasterizer::Impl::uploadMaterials(const RasterGeometry& s) {
  raster::MaterialTables tables = raster::materialTables(s);
  scene.materials = tables.summary;
  if (tables.triangleBits.empty()) tables.triangleBits.assign(1, 0u);
  if (tables.alphaIndex.empty()) tables.alphaIndex.assign(1, ALPHA_NO_TRIANGLE);
  if (tables.alphaTriangles.empty()) tables.alphaTriangles.assign(1, AlphaTriangle{});
  if (tables.materials.empty()) tables.materials.assign(1, AlphaMaterial{});
  static constexpr uint8_t kNoTexel = 0;
  const std::span<const uint8_t> texels = tables.summary.alphaTested && !s.alphaTexels.empty()
                                              ? s.alphaTexels
                                              : std::span<const uint8_t>(&kNoTexel, 1);
  scene.triangleBits = Buffer<uint32_t>(ctx, std::span<const uint32_t>(tables.triangleBits), CL_MEM_READ_ONLY);
  scene.alphaIndex = Buffer<uint32_t>(ctx, std::span<const uint32_t>(tables.alphaIndex), CL_MEM_READ_ONLY);
  scene.alphaTriangles =
      Buffer<AlphaTriangle>(ctx, std::span<const AlphaTriangle>(tables.alphaTriangles), CL_MEM_READ_ONLY);
  scene.alphaMaterials = Buffer<AlphaMaterial>(ctx, std::span<const AlphaMaterial>(tables.materials), CL_MEM_READ_ONLY);
  scene.alphaTexels = Buffer<uint8_t>(ctx, texels, CL_MEM_READ_ONLY);
}

// Capacities: the caller's initial ones, else estimates from the scene and grid; then buffers to match.
void Rasterizer::Impl::sizeQueues(const raster::Plan& plan) {
  raster::Queues& q = queues;
  if (!capacitiesChosen) {
    const size_t t = scene.triangleCount;
    auto pick = [&](size_t chosen, size_t estimate, size_t limit) {
      return static_cast<uint32_t>(std::min({chosen != 0 ? chosen : estimate, capacities.maxEntries, limit}));
    };
    const size_t limit = RASTER_SATURATED - 1;  // positions are 32-bit
    q.extraCapacity = pick(capacities.extraTriangles, 1024 + t / 8, limit - t);
    q.binCapacity = pick(capacities.binEntries, 4096 + 2 * t, limit);
    q.tileCapacity = pick(capacities.tileEntries, 16384 + 4 * t + 2 * plan.tiles, limit);
    capacitiesChosen = true;
  }
  const size_t records = size_t{scene.triangleCount} + q.extraCapacity;
  if (q.records.size() != records) q.records.allocate(ctx, records);
  if (q.counters.empty()) {
    q.counters.allocate(ctx, 1);
    for (Buffer<uint32_t>* b : {&q.binCount, &q.binOffset, &q.binCursor, &q.binTileTotal, &q.binTileBase})
      b->allocate(ctx, RASTER_MAX_BINS);
  }
  if (q.tileCount.size() < plan.tiles) {
    q.tileCount.allocate(ctx, plan.tiles);
    q.tileOffset.allocate(ctx, plan.tiles);
  }
  if (q.binEntries.size() != q.binCapacity) {
    q.binEntries.allocate(ctx, q.binCapacity);
    q.binTiles.allocate(ctx, q.binCapacity);
  }
  if (q.tileEntries.size() != q.tileCapacity) q.tileEntries.allocate(ctx, q.tileCapacity);
}

// Grows `capacity` when the run asked for more; throws past the hard maximum. Returns whether it grew.
// `indexLimit`: the most entries whose positions the kernels can form in 32 bits.
bool Rasterizer::Impl::grow(const char* queue, const char* kernel, uint32_t& capacity, uint64_t requested,
                            size_t recordBytes, uint64_t indexLimit) {
  if (requested <= capacity) return false;
  const uint64_t hardMax =
      std::min<uint64_t>({capacities.maxEntries, ctx.info().maxAllocBytes / recordBytes, indexLimit});
  if (requested > hardMax)
    throw ClError(CL_OUT_OF_RESOURCES,
                  fmt::format("{} queue needs {} entries (capacity {}), more than the hard maximum {}", queue,
                              requested, capacity, hardMax),
                  kernel, "raster");
  capacity = static_cast<uint32_t>(std::min<uint64_t>(requested + requested / 4, hardMax));
  return true;
}

void Rasterizer::Impl::run(const raster::Plan& plan, Buffer<float>& depth, Buffer<uint32_t>& triangleIds,
                           Buffer<uint32_t>* emptyTiles, Buffer<uint32_t>* casterFree) {
  stats = RasterStats{};
  stats.trianglesIn = scene.triangleCount;
  if (plan.empty()) return;
  if (noEmptyTiles.empty()) noEmptyTiles.allocate(ctx, 1);
  if (emptyTiles == nullptr) emptyTiles = &noEmptyTiles;
  if (casterFree == nullptr) casterFree = &noEmptyTiles;
  for (int round = 0;; ++round) {
    if (round == kMaxRounds)
      throw std::logic_error(fmt::format("raster: queues still overflow after {} rounds", kMaxRounds));
    sizeQueues(plan);
    stages.record(plan, scene, queues, depth, triangleIds, *emptyTiles, *casterFree);
    const RasterCounters counters = queues.counters.download(ctx).front();
    stats.trianglesSetUp = counters.setUp;
    stats.binEntries = counters.binEntries;
    stats.tileEntries = counters.tileEntries;
    std::copy(std::begin(counters.casterBox), std::end(counters.casterBox), std::begin(stats.casterBox));
    const uint64_t indexLimit = RASTER_SATURATED - 1;  // record and queue positions are 32-bit
    bool grew = grow("extra triangle", "setup_triangles", queues.extraCapacity, counters.extraTriangles,
                     sizeof(RasterTriangle), indexLimit - scene.triangleCount);
    grew |= grow("bin", "bin_fill", queues.binCapacity, counters.binEntries, sizeof(uint32_t), indexLimit);
    grew |= grow("tile", "coarse_fill", queues.tileCapacity, counters.tileEntries, sizeof(uint32_t), indexLimit);
    if (!grew) return;
    ++stats.retries;
  }
}

Rasterizer::Rasterizer(Context& ctx) : impl_(std::make_unique<Impl>(ctx)) {}
Rasterizer::~Rasterizer() = default;

void Rasterizer::setGeometry(const RasterGeometry& geometry) { impl_->upload(geometry); }

void Rasterizer::setCapacities(const RasterCapacities& capacities) {
  impl_->capacities = capacities;
  impl_->capacitiesChosen = false;
}

const Buffer<uint32_t>& Rasterizer::objectIds() const { return impl_->scene.objectIds; }

const RasterStats& Rasterizer::stats() const { return impl_->stats; }

void Rasterizer::draw(const RasterView& view, RasterTargets& targets) {
  raster::Plan plan =
      raster::makePlan(view, impl_->scene.triangleCount, impl_->scene.vertexCount, impl_->scene.materials);
  impl_->chooseSolidSides(view, plan);
  impl_->chooseCasters(view, plan);
  ensureTarget(impl_->ctx, targets.depth, plan, std::numeric_limits<float>::infinity());
  // RasterView::recordCasterTiles: the record names this draw once it is made.
  targets.casterFreeKey = {};
  Buffer<uint32_t>* casterFree = nullptr;
  if (view.recordCasterTiles) {
    if (!view.casterLight || view.scissor || view.tileMask != nullptr)
      throw std::invalid_argument(
          "raster view: caster tiles are recorded for a light's whole viewport (casterLight, "
          "no scissor, no tile mask)");
    if (!plan.empty()) {
      targets.casterFree.allocate(impl_->ctx, plan.tiles);
      plan.params.casterTiles = 1;
      plan.params.receiverReach = std::max(view.receiverReach, -1);
      casterFree = &targets.casterFree;
    }
  } else if (view.receiverReach >= 0) {
    throw std::invalid_argument("raster view: a receiver reach needs the caster tiles recorded (recordCasterTiles)");
  }
  const auto recorded = [&] {
    if (casterFree == nullptr) return;
    targets.casterFreeKey = {targets.depth.get()(), nullptr, view.width, view.height};
    targets.casterBox = casterTilesBox(impl_->stats.casterBox);
  };
  if (view.writeTriangleIds) {
    ensureTarget(impl_->ctx, targets.triangleId, plan, kNoTriangle);
  } else {
    plan.params.skipIds = 1;
    if (targets.triangleId.empty()) targets.triangleId.allocate(impl_->ctx, 1);  // an argument fine never writes
  }
  // RasterTargets::keepEmptyTiles: the record is valid for the buffers, viewport and id writing it was made with;
  // fresh (all tiles unknown) otherwise. Queue overflow reruns fine within run(), which keeps the record true round by
  // round.
  if (!targets.keepEmptyTiles || !impl_->stages.keepsEmptyTiles()) {
    targets.forgetEmptyTiles();
    impl_->run(plan, targets.depth, targets.triangleId, nullptr, casterFree);
    recorded();
    return;
  }
  const RasterTargets::EmptyTilesKey key{
      targets.depth.get()(), view.writeTriangleIds ? targets.triangleId.get()() : nullptr, view.width, view.height};
  if (!(targets.emptyTilesKey == key)) {
    targets.emptyTiles.allocate(impl_->ctx, plan.tiles);
    targets.emptyTiles.fill(impl_->ctx, 0u);
    targets.emptyTilesKey = key;
  }
  plan.params.emptyTiles = 1;
  impl_->run(plan, targets.depth, targets.triangleId, &targets.emptyTiles, casterFree);
  recorded();
}

RasterTileLists Rasterizer::drawTileLists(const RasterView& view) {
  if (view.scissor) throw std::invalid_argument("raster view: tile lists cover the whole viewport (no scissor)");
  raster::Plan plan =
      raster::makePlan(view, impl_->scene.triangleCount, impl_->scene.vertexCount, impl_->scene.materials);
  plan.params.conservative = 1;
  impl_->chooseCasters(view, plan);
  Context& ctx = impl_->ctx;
  if (impl_->noDepth.empty()) impl_->noDepth.allocate(ctx, 1), impl_->noIds.allocate(ctx, 1);
  impl_->run(plan, impl_->noDepth, impl_->noIds);
  const raster::Queues& q = impl_->queues;
  return {&q.tileCount, &q.tileOffset, &q.tileEntries, plan.params.tilesX, plan.params.tilesY,
          impl_->stats.tileEntries};
}

const raster::SceneBuffers& Rasterizer::deviceScene() const { return impl_->scene; }

raster::CasterTest Rasterizer::casterTest(const RasterLight& light) const { return impl_->casterTest(light); }

void Rasterizer::drawGBuffer(const RasterView& view, GBuffer& g) {
  const raster::Plan plan =
      raster::makePlan(view, impl_->scene.triangleCount, impl_->scene.vertexCount, impl_->scene.materials);
  if (view.tileMask != nullptr)  // gbuffer_resolve would read the untouched tiles' stale ids
    throw std::invalid_argument("raster view: a tile mask is for shadow-map draws, not the G-buffer");
  if (plan.params.generalProjection)  // the G-buffer reconstructs positions from separable pixel rays (depth.h)
    throw std::invalid_argument(
        "raster view: the G-buffer needs an OpenGL-style perspective or orthographic projection, not a general "
        "projective matrix");
  Context& ctx = impl_->ctx;
  g.width = view.width, g.height = view.height;
  ensureTarget(ctx, g.depth, plan, std::numeric_limits<float>::infinity());
  ensureTarget(ctx, g.triangleId, plan, kNoTriangle);
  ensureTarget(ctx, g.position, plan, cl_float4{});
  ensureTarget(ctx, g.normal, plan, cl_float4{});
  ensureTarget(ctx, g.objectId, plan, kNoTriangle);
  impl_->run(plan, g.depth, g.triangleId);
  if (!plan.empty()) impl_->stages.gbuffer(plan, impl_->scene, g);
}

}  // namespace penumbra
