// The binned compute rasterizer's host interface (in the spirit of Laine & Karras, "High-Performance
// Software Rasterization on GPUs", HPG 2011): triangle setup -> bin -> coarse -> fine, each stage its own
// kernel file in raster/. Used for light-view depth maps and the camera's G-buffer. Alpha-tested materials (glTF
// MASK, BLEND drawn as MASK) discard fragments below their cutoff in every draw; opaque triangles draw as before.
#pragma once

#include <array>
#include <cstdint>
#include <glm/glm.hpp>
#include <memory>
#include <optional>

#include "host/cl/buffer.h"
#include "host/cl/context.h"
#include "raster/constants.h"
#include "raster/geometry.h"

namespace penumbra {

namespace raster {
struct SceneBuffers;
class CasterTest;
}

inline constexpr int kRasterTileSize = RASTER_TILE_SIZE;  // pixels per side of a tile: RasterView::tileMask's unit

inline constexpr uint32_t kNoTriangle = 0xffffffffu;  // triangle id of background pixels

// What the depth buffer stores for a covered pixel (background is +INFINITY in every mode).
enum class DepthMode : int {
  kNdc = 0,       // window-space depth in [0, 1] (z_ndc * 0.5 + 0.5), as a hardware depth buffer
  kViewZ = 1,     // linear eye-space depth -z_eye (perspective and orthographic): what filtering wants
  kDistance = 2,  // Euclidean distance from the eye (world units): for omnidirectional/point-light tests
};

struct Scissor {
  int x0 = 0, y0 = 0, x1 = 0, y1 = 0;  // pixels [x0, x1) x [y0, y1)
};

// A light as the caster test sees it (RasterView::casterLight): a ball holding a spot or point light (its disk or
// sphere), or the cone of directions towards a sun.
struct RasterLight {
  bool directional = false;
  glm::vec3 position{0.0f};    // ball: the centre
  float radius = 0.0f;         // ball: world units (0: a point)
  glm::vec3 towards{0.0f};     // cone: unit direction from the scene towards the light
  float angularRadius = 0.0f;  // cone: radians, below pi / 2
};

struct RasterView {
  glm::mat4 view{1.0f};  // world -> eye
  // eye -> clip, OpenGL convention. Separable: perspective (glm::perspective/frustum: w_c = -k z_eye) or
  // orthographic (glm::ortho: w_c constant); x_c may depend on x_eye and z_eye only, y_c on y_eye and z_eye, z_c on
  // z_eye; near and far come from it. General (any other invertible projective matrix, e.g. a LiSPSM warp whose w_c
  // depends on an eye axis perpendicular to z): only with DepthMode::kViewZ and draw(), the stored depth still
  // -z_eye; clipped at the near plane z_c = -w_c and the guard band, with no far plane. draw() and drawGBuffer()
  // throw std::invalid_argument for other matrices (singular ones, general ones in other modes) or a bad size.
  glm::mat4 projection{1.0f};
  int width = 0, height = 0;  // 1x1 .. 8192x8192
  DepthMode depthMode = DepthMode::kViewZ;
  bool cullBackFaces = false;      // counter-clockwise front faces
  // Cull the back faces of triangles whose material is single-sided (glTF doubleSided false): the camera's G-buffer.
  // Shadow maps leave it off: a caster blocks light whichever side faces the light (README, Double-sided).
  bool cullSingleSided = false;
  std::optional<Scissor> scissor;  // pixels outside are left untouched
  // draw() only: one entry per 8x8 tile (RASTER_TILE_SIZE) of the viewport, row-major from the bottom row, at least
  // ceil(width / 8) * ceil(height / 8) of them; tiles whose entry is 0 are left untouched, like pixels outside the
  // scissor, and cost nothing past binning. For passes that need scattered parts of a map (jittered).
  const Buffer<uint32_t>* tileMask = nullptr;
  // draw() with a separable projection only: leave out the triangles of solids (RasterGeometry::solids) that face away
  // from the projection's centre (its eye, or its direction for an orthographic view) where the centre lies outside
  // the solid's box. Along every ray from the centre the nearest surface of a solid faces the centre, so the depth and
  // triangle ids drawn are the same (up to which of two faces a texel centre exactly on a silhouette edge goes to),
  // for less work. Light views set it (host/views/views.h); a general (warped) projection ignores it.
  bool cullSolidsFarSides = false;
  // draw() only: false leaves RasterTargets::triangleId alone (not written, not even sized): a depth-only map, for the
  // techniques that read no ID buffer (a 4096^2 map writes 64 MiB less).
  bool writeTriangleIds = true;
  // draw() and drawTileLists(): the light a shadow map of depth comparisons (or izb's tile lists) is drawn for, whose
  // draw may leave out every triangle that cannot hide any part of it from any point of the uploaded geometry's
  // bounding box: the triangle's plane has the whole light strictly on one side and the box on that side too (up to
  // 10^-5 of the box's size, far below any depth bias). Receivers lie in that box, so no comparison a receiver makes
  // changes; the texels such a triangle held (a ground under everything, the walls of a room around its light) stay
  // empty, and no tile lists it. Not for maps whose texels are filtered as values (moments), which need the
  // receivers' own depths.
  std::optional<RasterLight> casterLight;
  // draw() with casterLight, no scissor and no tile mask: draw every triangle (the ones casterLight's test leaves out
  // too: a map whose texels are filtered as values) and record which 8x8 tiles no caster reaches
  // (RasterTargets::casterFreeTiles): where a min-max pyramid of the map's casters may take the texels as background.
  bool recordCasterTiles = false;
  // With recordCasterTiles, >= 0: a tile whose queue holds no caster and that lies farther than this many pixels from
  // the casters' box (RasterTargets::casterBox) is left as the background, undrawn, and recorded as caster-free: for a
  // map whose receivers are read only near its casters (vssm's moments and SAT over the window around them). -1: every
  // tile is drawn.
  int receiverReach = -1;
};

// Depth-only targets (shadow maps): width * height each, row-major, row 0 at the bottom (y up in NDC).
struct RasterTargets {
  Buffer<float> depth;          // per DepthMode; +INFINITY where nothing was drawn
  Buffer<uint32_t> triangleId;  // index into RasterGeometry::triangles, kNoTriangle where nothing was drawn (unless
                                // the view's writeTriangleIds is false)
  // Opt-in, for targets that draw() alone writes (a shadow map drawn frame after frame): draw() keeps a record of the
  // 8x8 tiles that hold only the background and does not rewrite a tile that has no triangle now and held only the
  // background before. On CPU devices (Stages::keepsEmptyTiles) the fine stage otherwise stores every empty tile each
  // frame (64 MiB for a 4096^2 map). Whoever writes or replaces the buffers other than through draw() calls
  // forgetEmptyTiles(); draw() notices by itself only a change of width or height, of id writing, or of buffer handle.
  bool keepEmptyTiles = false;
  void forgetEmptyTiles() { emptyTilesKey = {}, casterFreeKey = {}; }  // and casterFreeTiles' record
  // draw()'s record, per tile of the viewport (row-major from the bottom row): nonzero where the targets hold only the
  // background; valid for the buffers and viewport in emptyTilesKey.
  struct EmptyTilesKey {
    cl_mem depth = nullptr, triangleId = nullptr;  // triangleId: null where the draws write no ids
    int width = 0, height = 0;                     // the viewport: a tile's index names the same 8x8 pixels
    bool operator==(const EmptyTilesKey&) const = default;
  };
  Buffer<uint32_t> emptyTiles;
  EmptyTilesKey emptyTilesKey;
  // The record where it is kept and describes a width x height viewport of these targets' depth (the last draw's):
  // nonzero per 8x8 tile that holds only the background (+INFINITY), row-major from the bottom row; null otherwise.
  // What a min-max pyramid over the map need not read (host/stages/pyramid.h).
  const Buffer<uint32_t>* backgroundTiles(int width, int height) const {
    const bool valid = keepEmptyTiles && emptyTilesKey.depth != nullptr && emptyTilesKey.depth == depth.get()() &&
                       emptyTilesKey.width == width && emptyTilesKey.height == height;
    return valid ? &emptyTiles : nullptr;
  }
  // The record of a draw with RasterView::recordCasterTiles, per 8x8 tile as backgroundTiles: nonzero where no triangle
  // that can cast a shadow reaches the tile (its queue holds none: the tile's texels are background or non-casters,
  // which no light ray meets in front of a caster), valid while casterFreeKey names the last draw (ids not counted).
  Buffer<uint32_t> casterFree;
  EmptyTilesKey casterFreeKey;
  // With that record: the casters' box, the union of their triangles' candidate pixels widened to whole 8x8 tiles,
  // [x0, x1) x [y0, y1) as {x0, y0, x1, y1}; all 0 when no caster was drawn. With RasterView::receiverReach r, the
  // tiles no caster reaches outside the box widened by r pixels on every side hold the background.
  std::array<int, 4> casterBox{};
  const Buffer<uint32_t>* casterFreeTiles(int width, int height) const {
    const bool valid = casterFreeKey.depth != nullptr && casterFreeKey.depth == depth.get()() &&
                       casterFreeKey.width == width && casterFreeKey.height == height;
    return valid ? &casterFree : nullptr;
  }
};

// The camera's G-buffer, reconstructed exactly from the visible triangle per pixel.
struct GBuffer {
  int width = 0, height = 0;
  Buffer<float> depth;          // per DepthMode of the view; +INFINITY for background
  Buffer<cl_float4> position;   // world position (xyz), w = 1 where covered, 0 for background
  Buffer<cl_float4> normal;     // world shading normal (unit xyz, interpolated), w = geometric facing sign
  Buffer<uint32_t> triangleId;  // kNoTriangle for background
  Buffer<uint32_t> objectId;    // RasterGeometry::objectIds of the visible triangle, kNoTriangle for background
};

// What a conservative draw leaves (Rasterizer::drawTileLists): for every tile of the viewport, the triangles (indices
// into RasterGeometry::triangles) whose exact projection may touch any point of the tile's area, so an exact test of a point
// against the triangles of the tile it falls in misses no triangle that covers it. Tile t's entries are
// entries[offset[t] .. offset[t] + count[t]); a triangle clipped into a fan can appear more than once. Tiles are
// row-major from the bottom row. The buffers are the rasterizer's own: valid until its next draw.
struct RasterTileLists {
  const Buffer<uint32_t>* count = nullptr;
  const Buffer<uint32_t>* offset = nullptr;
  const Buffer<uint32_t>* entries = nullptr;
  int tilesX = 0, tilesY = 0;
  uint64_t entryCount = 0;  // sum of count over the drawn tiles
};

struct RasterStats {
  uint64_t trianglesIn = 0, trianglesSetUp = 0;  // after clipping, culling and dropping degenerates
  uint64_t binEntries = 0, tileEntries = 0;
  int retries = 0;  // grow-and-retry rounds after a capacity overflow
  uint32_t casterBox[4] = {0, 0, 0, 0};  // RasterCounters::casterBox (RasterViewParams::casterTiles draws)
};

// Queue capacities in entries. The rasterizer starts from `initial` (0: sized from the scene and view), grows a
// queue to what a run asked for and re-runs when one overflows, and throws ClError (CL_OUT_OF_RESOURCES, stage
// "raster", naming the queue and both sizes) when a queue would need more than `maxEntries` or the device's
// largest allocation. Tests set tiny initial capacities to force the grow-and-retry path.
struct RasterCapacities {
  size_t extraTriangles = 0;            // set-up records beyond one per input triangle (clipping fans)
  size_t binEntries = 0;                // (triangle, bin) pairs
  size_t tileEntries = 0;               // (triangle, tile) pairs
  size_t maxEntries = size_t{1} << 31;  // hard maximum of each queue (entries are 4 bytes, records 88)
};

// The float world -> clip matrix the snapping spec starts from (raster/setup.cl): projection * view, composed in
// double and rounded once.
glm::mat4 rasterClipMatrix(const RasterView& view);

class Rasterizer {
 public:
  explicit Rasterizer(Context& ctx);
  ~Rasterizer();
  Rasterizer(const Rasterizer&) = delete;
  Rasterizer& operator=(const Rasterizer&) = delete;

  // Uploads the world-space triangles once, with the alpha-tested triangles' texture coordinates, materials and alpha
  // textures (the atlas: RasterGeometry::alphaTexels) and the per-triangle material bits when they are needed; later
  // draws reuse them. Throws std::invalid_argument for inconsistent geometry or material data. (A Scene:
  // host/views/raster_scene.h's uploadScene.)
  void setGeometry(const RasterGeometry& geometry);

  // Rasterizes into targets (allocated/resized as needed to view.width * view.height and cleared inside
  // the scissor). Launches are reported to the context's profiler under the stage name "raster".
  void draw(const RasterView& view, RasterTargets& targets);
  void drawGBuffer(const RasterView& view, GBuffer& gbuffer);

  // A conservative draw of `view` (kViewZ or kNdc; the view's tile mask, when given, restricts which tiles get lists;
  // the scissor is not supported): setup, binning and coarse rasterization with every pixel rectangle dilated to its
  // whole area (RASTER_CONSERVATIVE_DILATION), and no fine stage. Triangles whose snapped projection has no area
  // (slivers, triangles seen edge-on) are kept. Grows its queues like draw().
  RasterTileLists drawTileLists(const RasterView& view);

  const RasterStats& stats() const;

  // The uploaded scene on the device (raster/stages.h): world positions, triangles and the alpha tables (alphaIndex,
  // alphaTriangles, alphaMaterials, alphaTexels), for kernels that test against the triangles the rasterizer draws.
  const raster::SceneBuffers& deviceScene() const;
  // RasterView::casterLight's test for `light` over the uploaded geometry's bounds, for callers that pick casters on
  // the host (izb's area-light lists). Throws as draw() does for a bad light.
  raster::CasterTest casterTest(const RasterLight& light) const;

  // RasterGeometry::objectIds of the uploaded scene on the device, one per triangle (0 where the scene gave none): what a
  // map's triangle ids resolve to for an object ID buffer.
  const Buffer<uint32_t>& objectIds() const;

  // Initial queue capacities and the hard maximum (see RasterCapacities); takes effect at the next draw.
  void setCapacities(const RasterCapacities& capacities);

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace penumbra
