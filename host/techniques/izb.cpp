// `izb`: exact hard shadows by an irregular z-buffer (kernels/izb.cl). The light grid is a light view fitted like a
// shadow map's (to the receivers the camera sees, or the whole scene), of map-size texels whose 8x8 tiles are the
// cells; the samples are binned into it by a counting sort, the casters drawn over it conservatively by the binned
// rasterizer (Rasterizer::drawTileLists, only the cells that hold samples), and each sample tested exactly against its
// cell's triangles. Memory: 4 bytes per pixel, 8 per sample of a chunk of at most --izb-chunk samples (more samples
// are processed in chunks of whole pixels, each with its own draw), 12 per cell, and the rasterizer's grown queues.
#include "kernels/shared/izb.h"

#include <fmt/format.h>

#include <algorithm>
#include <stdexcept>

#include "host/cl/kernel.h"
#include "host/techniques/registry.h"
#include "host/techniques/shadow_map.h"
#include "host/views/views.h"
#include "raster/stages.h"

namespace penumbra {
namespace {

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

struct IzbSettings {
  int gridSize = 0;  // map-size: the light grid's texels per side
  bool fitReceivers = true;
  int samples = 1;   // per pixel (izb_samples_of_choice)
  size_t chunk = 0;  // izb-chunk
  static IzbSettings from(const Params& params, int /*mapSize: izb's grid size has no auto*/) {
    return {params.getInt("map-size"), params.getInt("fit") == 1, izb_samples_of_choice(params.getInt("izb-samples")),
            static_cast<size_t>(params.get("izb-chunk"))};
  }
  bool operator==(const IzbSettings&) const = default;
};

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
    const uint32_t cellsX = static_cast<uint32_t>((grid.raster.width + IZB_CELL_TEXELS - 1) / IZB_CELL_TEXELS);
    const uint32_t cellsY = static_cast<uint32_t>((grid.raster.height + IZB_CELL_TEXELS - 1) / IZB_CELL_TEXELS);
    const uint32_t cells = cellsX * cellsY;
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

    IzbFrame f{};
    const glm::mat4 inverse(glm::inverse(glm::dmat4(rasterClipMatrix(cameraView(frame.camera, frame.scene.bounds())))));
    for (int r = 0; r < 4; ++r)
      for (int c = 0; c < 4; ++c) f.cameraInverse[r * 4 + c] = inverse[c][r];
    f.sceneRadius = frame.scene.triangles.empty() ? 0.0f : frame.scene.bounds().radius();
    f.width = static_cast<uint32_t>(g.width), f.height = static_cast<uint32_t>(g.height);
    f.samples = samples_, f.pattern = izb_pattern_offset(samples_);
    f.cells = cells;

    const raster::SceneBuffers& scene = frame.raster.deviceScene();
    f.alphaTested = scene.materials.alphaTested ? 1u : 0u;
    Kernel bin(ctx, "kernels/izb.cl", "izb_bin", "izb"), scanBlocks(ctx, "kernels/izb.cl", "izb_scan_blocks", "izb");
    Kernel scanSums(ctx, "kernels/izb.cl", "izb_scan_sums", "izb"),
        scanAdd(ctx, "kernels/izb.cl", "izb_scan_add", "izb");
    Kernel scatter(ctx, "kernels/izb.cl", "izb_scatter", "izb"), test(ctx, "kernels/izb.cl", "izb_test", "izb");
    uint64_t entries = 0;
    int chunks = 0;
    for (size_t begin = 0; begin < pixels; begin += pixelsPerChunk, ++chunks) {
      const size_t count = std::min(pixelsPerChunk, pixels - begin) * static_cast<size_t>(samples_);
      f.pixelBegin = static_cast<uint32_t>(begin), f.sampleCount = static_cast<uint32_t>(count);
      cellCount_.fill(ctx, 0u);
      cursor_.fill(ctx, 0u);
      // Bytes floors (Kernel::moves): bin reads each sample's pixel (position, normal, triangle id: 36 B, shared by
      // its samples) and writes its cell (4 B); scatter reads the cell and its start, writes the sorted index; test
      // reads the sorted index and the cell, then data-dependent triangle lists.
      bin.args(g.position, g.normal, g.triangleId, scene.positions, scene.triangles, f, gpu_, cellOf_, cellCount_,
               outside_)
          .moves(count / static_cast<size_t>(samples_) * 36 + count * 4)
          .launch(count, kPixelGroup);
      scan(scanBlocks, scanSums, scanAdd, cells);
      scatter.args(cellOf_, cellStart_, cursor_, sorted_, f.sampleCount).moves(count * 12).launch(count, kPixelGroup);
      grid.raster.tileMask = &cellCount_;
      const RasterTileLists lists = frame.raster.drawTileLists(grid.raster);
      entries += lists.entryCount;
      test.args(sorted_, cellOf_, cellStart_, cellCount_, g.position, g.normal, g.triangleId, scene.positions,
                scene.triangles, f, gpu_, *lists.count, *lists.offset, *lists.entries, scene.alphaIndex,
                scene.alphaTriangles, scene.alphaMaterials, scene.alphaTexels, occluded_)
          .moves(count * 8)
          .launch(count, kPixelGroup);
    }
    Kernel resolve(ctx, "kernels/izb.cl", "izb_resolve", "izb");
    resolve.args(g.position, occluded_, samples_, static_cast<uint32_t>(pixels), visibility)
        .moves(pixels * (16 + 4 + 4))
        .launch(pixels, kPixelGroup);
    const uint32_t outside = outside_.download(ctx).front();
    frame.attributes["penumbra:izb"] = fmt::format(
        "{} grid {}x{} texels ({}x{} cells), {} samples per pixel in {} chunk{}, {} triangle-cell entries, {} samples "
        "outside the grid (lit)",
        settings_.fitReceivers ? "receivers" : "scene", grid.raster.width, grid.raster.height, cellsX, cellsY,
        samples_, chunks, chunks == 1 ? "" : "s", entries, outside);
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

  // cellStart = exclusive scan of cellCount (kernels/izb.cl izb_scan_*).
  void scan(Kernel& blocks, Kernel& sums, Kernel& add, uint32_t cells) {
    const size_t groups = (cells + IZB_SCAN_BLOCK - 1) / IZB_SCAN_BLOCK;
    if (groups > IZB_SCAN_BLOCK) throw std::logic_error("izb: more cells than one scan of block sums covers");
    blocks.args(cellCount_, cellStart_, blockSums_, cells)
        .moves(uint64_t{cells} * 8)
        .launch(groups * IZB_SCAN_WG, IZB_SCAN_WG);
    sums.args(blockSums_, static_cast<uint32_t>(groups)).launch(IZB_SCAN_WG, IZB_SCAN_WG);
    add.args(cellStart_, blockSums_, cells).moves(uint64_t{cells} * 8).launch(cells, kPixelGroup);
  }

  int samples_;
  Buffer<LightViewGpu> gpu_;
  Buffer<uint32_t> cellOf_, sorted_, cellCount_, cellStart_, cursor_, blockSums_, occluded_, outside_;
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
      {"cube-guard", 8, 0, 2048,
       "Point lights: each cube face's grid reaches this many texels beyond its 90-degree square on every side"},
  };
  return {"izb",
          "Exact hard shadows: irregular z-buffer, each G-buffer sample tested against the triangles over its cell",
          params, makeTechnique<IrregularZBuffer>};
}

}  // namespace penumbra
