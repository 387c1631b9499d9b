// `fvsm`: fitted virtual shadow maps (Giegl & Wimmer, "Fitted Virtual Shadow Maps", GI 2007; Luksch sec. 8). The
// virtual map is the light's view fitted as sm's (--fit) at map-size * 2^L texels a side (L from --fvsm-max-size), as
// a quadtree whose nodes are map-size^2 tiles. Per frame:
//   1. kernels/fvsm.cl fvsm_request: every covered pixel's needed level (its screen step in base-map texels, shifted
//      by the quality xi), as a histogram per cell of the finest level's grid (Luksch's implementation computes the
//      bottom level of the tile-grid pyramid on the GPU too);
//   2. here: per cell, the level that all but --fvsm-outliers of its pixels are content with (Giegl & Wimmer's
//      statistical outlier rejection, as a quantile), then the top-down traversal of the pyramid: a node whose cells
//      need no finer level than its own is drawn, else its four children are visited (only those with pixels);
//      over the texel budget (--fvsm-budget) the deepest level allowed drops until the tiles fit, and the header
//      says so;
//   3. each tile drawn by the rasterizer into its slot of the atlas, cropped (crop matrix) from the base view with a
//      margin of texels on every side, so lookups near a tile's edge (normal offset, nearest texel) stay inside it;
//   4. fvsm_visibility: sm's hard test through the page table (finest cells -> tile), with the bias in the footprint
//      of the tile used.
#include "kernels/shared/fvsm.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <glm/glm.hpp>
#include <queue>
#include <tuple>
#include <utility>
#include <vector>

#include "host/cl/kernel.h"
#include "host/techniques/registry.h"
#include "host/techniques/shadow_map.h"
#include "host/views/views.h"
#include "kernels/shared/id_buffer.h"
#include "raster/stages.h"

namespace penumbra {
namespace {

// Tile views per visibility launch: __constant memory holds at least 64 KiB on every device (OpenCL 1.2's minimum),
// 315 LightViewGpu records.
constexpr size_t kViewsPerBatch = 256;

struct Leaf {
  int level = 0, x = 0, y = 0;  // quadtree node: level, and its position among the level's 2^level x 2^level tiles
};

// The quadtree over the finest grid's cells: per cell the level its pixels need (-1: no pixel) and its pixel count.
class TilePyramid {
 public:
  TilePyramid(std::vector<int> need, std::vector<uint64_t> pixels, int levels)
      : need_(std::move(need)), pixels_(std::move(pixels)), levels_(levels), cells_(1 << levels) {}

  // What a node covers: the deepest level one of its cells needs (-1: no pixel), and the pixels of the cells that
  // need a finer level than the node's (what splitting it would serve).
  struct Demand {
    int deepest = -1;
    uint64_t undersampled = 0;
  };
  Demand demand(const Leaf& node) const {
    const int span = cells_ >> node.level;
    Demand d;
    for (int y = node.y * span; y < (node.y + 1) * span; ++y)
      for (int x = node.x * span; x < (node.x + 1) * span; ++x) {
        const size_t c = static_cast<size_t>(y) * cells_ + x;
        d.deepest = std::max(d.deepest, need_[c]);
        if (need_[c] > node.level) d.undersampled += pixels_[c];
      }
    return d;
  }

  // The leaves of the fitted quadtree: starting from the root, the leaf whose split serves the most undersampled
  // pixels is split into its children that hold pixels, while the tiles stay within `budgetTiles`; leaves whose
  // cells need no finer level are final. `starved` gets the pixels left coarser than they need by the budget.
  std::vector<Leaf> fit(uint64_t budgetTiles, uint64_t& starved) const {
    struct Candidate {
      Leaf leaf;
      uint64_t undersampled;
      bool operator<(const Candidate& o) const {  // max-heap on pixels served, then a fixed order
        if (undersampled != o.undersampled) return undersampled < o.undersampled;
        if (leaf.level != o.leaf.level) return leaf.level > o.leaf.level;
        return std::tie(leaf.y, leaf.x) > std::tie(o.leaf.y, o.leaf.x);
      }
    };
    std::vector<Leaf> leaves;
    std::priority_queue<Candidate> open;
    starved = 0;
    auto add = [&](const Leaf& node, const Demand& d) {  // d.deepest >= 0: the node holds pixels
      if (d.deepest > node.level && node.level < levels_)
        open.push({node, d.undersampled});
      else
        leaves.push_back(node);
    };
    if (const Demand root = demand(Leaf{}); root.deepest >= 0) add(Leaf{}, root);
    while (!open.empty()) {
      const Candidate best = open.top();
      open.pop();
      Leaf children[4];
      Demand demands[4];
      uint64_t holding = 0;  // children with pixels: the tiles the split draws instead of this one
      for (int k = 0; k < 4; ++k) {
        children[k] = child(best.leaf, k), demands[k] = demand(children[k]);
        holding += demands[k].deepest >= 0;
      }
      if (leaves.size() + open.size() + holding > budgetTiles) {
        leaves.push_back(best.leaf);  // over the budget: drawn coarser than its pixels need
        starved += best.undersampled;
        continue;
      }
      for (int k = 0; k < 4; ++k)
        if (demands[k].deepest >= 0) add(children[k], demands[k]);
    }
    return leaves;
  }

 private:
  static Leaf child(const Leaf& node, int k) { return {node.level + 1, 2 * node.x + (k & 1), 2 * node.y + (k >> 1)}; }

  std::vector<int> need_;
  std::vector<uint64_t> pixels_;
  int levels_, cells_;
};

struct FvsmSettings {
  MapSettings map;  // map-size: the tile
  int receiverPlane = 1;
  double maxSize = 0;  // fvsm-max-size
  float quality = 0;
  double outliers = 0;
  double budget = 0;  // fvsm-budget, texels
  bool exactEdges = false;
  static FvsmSettings from(const Params& params, int mapSize) {
    return {MapSettings::from(params, mapSize), params.getInt("receiver-plane"),
            params.get("fvsm-max-size"),        static_cast<float>(params.get("fvsm-quality")),
            params.get("fvsm-outliers"),        params.get("fvsm-budget"),
            params.getInt("exact-edges") != 0};
  }
  bool operator==(const FvsmSettings&) const = default;
};

class FittedVirtualShadowMap final : public TechniqueOf<FvsmSettings> {
 public:
  using TechniqueOf::TechniqueOf;

  void render(ShadowFrame& frame, Buffer<float>& visibility) override {
    Context& ctx = frame.ctx;
    const GBuffer& g = frame.gbuffer;
    const size_t pixels = static_cast<size_t>(g.width) * static_cast<size_t>(g.height);
    const int tile = settings_.map.size;
    const int levels = std::clamp(
        static_cast<int>(std::floor(std::log2(settings_.maxSize / static_cast<double>(tile)) + 1e-9)), 0,
        FVSM_MAX_LEVELS);
    const int cells = 1 << levels;
    const ReceiverBias bias = settings_.map.receiverBias();
    // Tiles overlap by this many texels on every side: the normal offset and the nearest texel of a receiver in the
    // tile's nominal square stay inside the tile.
    const int margin = static_cast<int>(std::ceil(bias.normalOffset)) + 2;
    const LightView base =
        fitLightView(frame.light, frame.scene.bounds(), tile, settings_.map.fit.fitReceivers ? &frame.receivers : nullptr,
                     static_cast<float>(margin));
    baseGpu_.allocate(ctx, 1, CL_MEM_READ_ONLY);
    baseGpu_.upload(ctx, std::span<const LightViewGpu>(&base.gpu, 1));

    // 1. What each cell's pixels need.
    const size_t bins = static_cast<size_t>(cells) * cells * static_cast<size_t>(levels + 1);
    histogram_.allocate(ctx, bins);
    histogram_.fill(ctx, 0u);
    const uint32_t width = static_cast<uint32_t>(g.width), height = static_cast<uint32_t>(g.height);
    Kernel request(ctx, "kernels/fvsm.cl", "fvsm_request", "fvsm");
    request
        .args(g.position, g.normal, width, height, baseGpu_, static_cast<uint32_t>(cells), levels, settings_.quality,
              histogram_)
        .moves(pixels * kVisibilityBytesPerPixel)
        .launch(pixels, pixelGroup(frame.ctx));
    const std::vector<uint32_t> counts = histogram_.download(ctx);

    // 2. Outlier rejection per cell, the quadtree, the budget.
    const double outliers = settings_.outliers;
    std::vector<int> need(static_cast<size_t>(cells) * cells, -1);
    std::vector<uint64_t> cellPixels(need.size(), 0);
    uint64_t covered = 0;
    for (size_t c = 0; c < need.size(); ++c) {
      const uint32_t* h = &counts[c * static_cast<size_t>(levels + 1)];
      uint64_t total = 0;
      for (int l = 0; l <= levels; ++l) total += h[l];
      if (total == 0) continue;
      const auto allowed = static_cast<uint64_t>(outliers * static_cast<double>(total));  // pixels left undersampled
      uint64_t above = total;
      int level = 0;
      for (; level < levels; ++level) {
        above -= h[level];
        if (above <= allowed) break;
      }
      need[c] = level, cellPixels[c] = total, covered += total;
    }
    const uint64_t tileTexels = static_cast<uint64_t>(tile) * static_cast<uint64_t>(tile);
    const uint64_t budget = static_cast<uint64_t>(settings_.budget);
    uint64_t starved = 0;
    const std::vector<Leaf> leaves = TilePyramid(std::move(need), std::move(cellPixels), levels)
                                         .fit(std::max<uint64_t>(1, budget / tileTexels), starved);
    int deepest = 0, shallowest = levels;
    for (const Leaf& leaf : leaves)
      deepest = std::max(deepest, leaf.level), shallowest = std::min(shallowest, leaf.level);

    // The page table and the tiles' views.
    std::vector<uint32_t> page(static_cast<size_t>(cells) * cells, FVSM_NO_LEAF);
    std::vector<int32_t> leafLevels;
    std::vector<LightView> views;
    for (size_t k = 0; k < leaves.size(); ++k) {
      const Leaf& leaf = leaves[k];
      const int span = cells >> leaf.level;
      for (int y = leaf.y * span; y < (leaf.y + 1) * span; ++y)
        for (int x = leaf.x * span; x < (leaf.x + 1) * span; ++x)
          page[static_cast<size_t>(y) * cells + x] = static_cast<uint32_t>(k);
      const float part = 2.0f / static_cast<float>(1 << leaf.level);  // the node's NDC extent in the base view
      const glm::vec2 lo(-1.0f + part * static_cast<float>(leaf.x), -1.0f + part * static_cast<float>(leaf.y));
      const float grow = part * static_cast<float>(margin) / static_cast<float>(tile - 2 * margin);
      views.push_back(cropLightView(base, lo - grow, lo + part + grow, tile));
      leafLevels.push_back(leaf.level);
    }

    // 3. The tiles, each into its slot of the atlas.
    visibility.fill(ctx, 1.0f);
    level_.allocate(ctx, pixels);
    level_.fill(ctx, -1.0f);
    if (!leaves.empty()) {
      const bool ids = settings_.exactEdges;  // without exact edges the tiles are depth only
      atlasDepth_.allocate(ctx, leaves.size() * tileTexels);
      atlasIds_.allocate(ctx, ids ? leaves.size() * tileTexels : 1);
      for (size_t k = 0; k < leaves.size(); ++k) {
        RasterTargets slot;  // a fresh region of the atlas each frame: no empty tiles kept (RasterTargets)
        slot.depth = atlasDepth_.region(ctx, k * tileTexels, tileTexels);
        slot.triangleId = ids ? atlasIds_.region(ctx, k * tileTexels, tileTexels) : atlasIds_.region(ctx, 0, 1);
        views[k].raster.writeTriangleIds = ids;
        views[k].raster.casterLight = rasterLightOf(frame.light);  // depth comparisons only (ShadowMap::castersOnly)
        frame.raster.draw(views[k].raster, slot);
      }
      page_.allocate(ctx, page.size(), CL_MEM_READ_ONLY);
      page_.upload(ctx, std::span<const uint32_t>(page));
      leafLevels_.allocate(ctx, leafLevels.size(), CL_MEM_READ_ONLY);
      leafLevels_.upload(ctx, std::span<const int32_t>(leafLevels));

      // 4. The lookups, a batch of tile views at a time.
      Kernel lookup(ctx, "kernels/fvsm.cl", "fvsm_visibility", "shade");
      const ShadeFrame shade = shadeFrame(frame, settings_.map, settings_.receiverPlane, ID_BUFFER_OFF);
      const raster::SceneBuffers& scene = frame.raster.deviceScene();
      const float sceneRadius = frame.scene.boundingRadius();
      batches_.resize(std::max(batches_.size(), (leaves.size() + kViewsPerBatch - 1) / kViewsPerBatch));
      for (size_t begin = 0; begin < leaves.size(); begin += kViewsPerBatch) {
        const size_t count = std::min(kViewsPerBatch, leaves.size() - begin);
        std::vector<LightViewGpu> batch;
        for (size_t k = begin; k < begin + count; ++k) batch.push_back(views[k].gpu);
        Buffer<LightViewGpu>& gpu = batches_[begin / kViewsPerBatch];
        gpu.allocate(ctx, batch.size(), CL_MEM_READ_ONLY);
        gpu.upload(ctx, std::span<const LightViewGpu>(batch));
        const FvsmBatch batchInfo{static_cast<uint32_t>(begin),
                                  static_cast<uint32_t>(count),
                                  static_cast<uint32_t>(cells),
                                  ids ? 1u : 0u,
                                  scene.materials.alphaTested ? 1u : 0u,
                                  sceneRadius,
                                  scene.triangleCount};
        lookup
            .args(g.position, g.normal, atlasDepth_, atlasIds_, baseGpu_, shade, gpu, page_, leafLevels_, batchInfo,
                  g.triangleId, scene.positions, scene.triangles, scene.alphaIndex, scene.alphaTriangles,
                  scene.alphaMaterials, scene.alphaTexels, visibility, level_)
            .moves(pixels * kVisibilityBytesPerPixel)
            .launch(pixels, pixelGroup(frame.ctx));
      }
    }
    const uint64_t rendered = leaves.size() * tileTexels;
    const uint64_t uniform = static_cast<uint64_t>(tile) << deepest;
    frame.attributes["penumbra:fvsm"] = fmt::format(
        "{} tiles of {}x{} (levels {}..{} of {}, virtual {}x{}), {} texels drawn, {:.3g}% of the uniform {}x{} map of "
        "the same finest texel{}",
        leaves.size(), tile, tile, leaves.empty() ? 0 : shallowest, deepest, levels, tile << levels, tile << levels,
        rendered, 100.0 * static_cast<double>(rendered) / static_cast<double>(uniform * uniform), uniform, uniform,
        starved > 0
            ? fmt::format("; the budget of {} texels left {} of {} pixels ({:.3g}%) coarser than they need", budget,
                          starved, covered, 100.0 * static_cast<double>(starved) / static_cast<double>(covered))
            : "");
  }

  void addDebugChannels(Context& ctx, Image& image) override {
    if (!level_.empty()) image.add("level.Y", level_.download(ctx));
  }

 private:
  Buffer<LightViewGpu> baseGpu_;
  std::vector<Buffer<LightViewGpu>> batches_;
  Buffer<uint32_t> histogram_, page_;
  Buffer<int32_t> leafLevels_;
  Buffer<float> atlasDepth_, level_;
  Buffer<uint32_t> atlasIds_;
};

}  // namespace

TechniqueInfo fvsmTechnique() {
  std::vector<ParamSpec> params = shadowMapParams();
  unscaledNormalOffset(params);
  fixMapSize(params, "the tile size; the virtual map's size follows the receivers");
  ParamSpec& tile = paramNamed(params, "map-size");
  tile.defaultValue = 1024, tile.min = 64, tile.max = 8192;
  tile.help =
      "Tile width and height in texels (the quadtree root's map); the virtual map is up to --fvsm-max-size "
      "texels a side";
  params.push_back(receiverPlaneParam());
  params.push_back(exactEdgesParam());
  params.push_back({"fvsm-max-size", 32768, 64, 1 << 20,
                    "Virtual map width and height in texels at the quadtree's deepest level (map-size * 2^levels, "
                    "rounded down to a power-of-two multiple of map-size, at most 2^10 tiles a side)"});
  params.push_back({"fvsm-quality", 1.0, 0.0625, 16,
                    "Quality xi: texels per pixel step a tile must reach (1: one texel per pixel; 0.5 halves the "
                    "resolution everywhere, a level coarser)"});
  params.push_back({"fvsm-outliers", 0.02, 0, 0.5,
                    "Share of a page cell's pixels that may stay undersampled: outliers do not refine the cell"});
  params.push_back({"fvsm-budget", 64.0 * (1 << 20), 4096, 4.0 * (1u << 30),
                    "Texels drawn per frame at most (8 bytes each on the device); within it the tiles that serve the "
                    "most undersampled pixels are refined first, and the header counts the pixels left coarser"});
  return {"fvsm",
          "Fitted virtual shadow maps: quadtree tiles drawn only where the receivers need them",
          params,
          makeTechnique<FittedVirtualShadowMap>,
          /*pointLightRefusal=*/{},
          "it draws quadtree tiles of the light's view at the resolution each region of receivers asks for: a draw of "
          "the scene per tile, not one map"};
}

}  // namespace penumbra
