// `pcss`: percentage-closer soft shadows for spot disk lights and sun disks (kernels/pcss.cl): blocker
// search, penumbra from similar triangles, PCF, on grids or rotated Poisson disks. Debug channel: the average blocker
// depth.
#include <fmt/format.h>

#include <algorithm>
#include <string>

#include "host/stages/pyramid.h"
#include "host/techniques/poisson.h"
#include "host/techniques/registry.h"
#include "host/techniques/shadow_map.h"
#include "kernels/shared/id_buffer.h"
#include "kernels/shared/shade.h"

namespace penumbra {
namespace {

// --pcss-max-radius auto: a 32nd of the map's side, the same width in the scene at every size, so that a larger map
// never reaches less far (at 4096^2 a fixed 64 cut default.json's contact-free penumbrae: MAE 0.00211 against 0.00165
// with 128, 480x270, 256-spp reference); and at least 64 texels, the fixed reach before, since the map is small exactly
// where the penumbrae are wide (--map-size auto draws 384-768^2 for stacked-planes under a light of radius 2-4: a 32nd
// of that, 12-24 texels, tripled the MAE, 0.0092 against 0.0297 at radius 4). The taps are as many at any reach.
constexpr AutoReach kMaxRadius{32, 64};

// --pcss-search-taps / --pcss-filter-taps: fixed taps per side, or under auto (the default) the most per side of the
// counts kernels/pcss.cl pcss_tap_count takes from each pixel's region, --pcss-*-taps-max.
int tapsOf(const Params& params, const std::string& name) {
  return params.getInt(params.isAuto(name) ? name + "-max" : name);
}

struct PcssSettings {
  MapSettings map;
  int receiverPlane = 1;
  int searchTaps = 0, filterTaps = 0;
  int autoTaps = 0;  // PCSS_AUTO_* bits
  float maxRadius = 0;
  int pattern = SHADE_PATTERN_POISSON;  // SHADE_PATTERN_*
  bool adaptive = false;                // pcss-search adaptive
  bool umbra = true;                    // pcss-umbra on
  bool stackedTrace = true;             // pcss-stacked-trace on
  bool sparseTaps = true;               // pcss-sparse-taps on
  static PcssSettings from(const Params& params, int mapSize) {
    const MapSettings map = MapSettings::from(params, mapSize);
    return {map,
            params.getInt("receiver-plane"),
            tapsOf(params, "pcss-search-taps"),
            tapsOf(params, "pcss-filter-taps"),
            (params.isAuto("pcss-search-taps") ? PCSS_AUTO_SEARCH : 0) |
                (params.isAuto("pcss-filter-taps") ? PCSS_AUTO_FILTER : 0),
            kMaxRadius.texels(params, "pcss-max-radius", map.size),
            params.getInt("pcss-pattern"),
            params.getInt("pcss-search") == kSearchAdaptive,
            params.getInt("pcss-umbra") == 1,
            params.getInt("pcss-stacked-trace") == 1,
            params.getInt("pcss-sparse-taps") == 1};
  }
  bool operator==(const PcssSettings&) const = default;
};

class PercentageCloserSoft final : public TechniqueOf<PcssSettings> {
 public:
  using TechniqueOf::TechniqueOf;

  void render(ShadowFrame& frame, Buffer<float>& visibility) override {
    const PcssSettings& s = settings_;
    const bool adaptive = s.adaptive;
    map_.castersOnly = true;  // depth comparisons only: the map leaves out what can shadow no receiver
    // Adaptive: the pyramid's top is the nearest caster drawn, no reduction of its own.
    renderShadowMap(frame, s.map, map_, s.maxRadius, adaptive ? MapNear::Fitted : MapNear::Drawn);
    blocker_.allocate(frame.ctx, visibility.size());
    const int searchTaps = s.searchTaps, filterTaps = s.filterTaps;
    const int pattern = s.pattern;
    if (searchDisk_.empty()) {
      // taps^2 points each (the grid's count; the most under auto, whose pixels take a prefix); their own seeds, so
      // the two patterns do not line up.
      const int searchCount = pattern == SHADE_PATTERN_POISSON ? searchTaps * searchTaps : 1;
      const int filterCount = pattern == SHADE_PATTERN_POISSON ? filterTaps * filterTaps : 1;
      const std::vector<cl_float2> search = progressivePoissonDisk(searchCount, 2);
      const std::vector<cl_float2> filter = progressivePoissonDisk(filterCount, 1);
      searchDisk_ = Buffer<cl_float2>(frame.ctx, std::span<const cl_float2>(search), CL_MEM_READ_ONLY);
      filterDisk_ = Buffer<cl_float2>(frame.ctx, std::span<const cl_float2>(filter), CL_MEM_READ_ONLY);
    }
    if (adaptive) {  // the map's min-max pyramid above the map: the nearest caster over any region
      const uint32_t size = static_cast<uint32_t>(map_.view.gpu.width);
      tightenMapNear(
          frame, s.map, map_,
          pyramid_.build(frame.ctx, map_.targets.depth, size, size, map_.targets.backgroundTiles(size, size)).s[0]);
    } else {
      pyramid_.allocate(frame.ctx, 1, 1);  // unused arguments still need buffers
    }
    const ShadeFrame shade = shadeFrame(frame, s.map, s.receiverPlane, ID_BUFFER_OFF);
    const PcssShade pcss{searchTaps,
                         filterTaps,
                         s.maxRadius,
                         pattern,
                         static_cast<int>(adaptive),
                         adaptive ? pyramid_.count() : 0u,
                         s.autoTaps,
                         static_cast<int>(s.umbra),
                         static_cast<int>(s.stackedTrace),
                         static_cast<int>(s.sparseTaps)};
    launchVisibility(frame, map_, shade, "kernels/pcss.cl", "pcss_visibility", visibility, pcss, searchDisk_,
                     filterDisk_, pyramid_.pyramid(), pyramid_.levels(), blocker_);
  }

  void addDebugChannels(Context& ctx, Image& image) override { image.add("blocker.Z", blocker_.download(ctx)); }

 private:
  ShadowMap map_;
  MinMaxLevels pyramid_;  // --pcss-search adaptive: the map's min-max pyramid above it
  Buffer<cl_float2> searchDisk_, filterDisk_;
  Buffer<float> blocker_;
};

}  // namespace

TechniqueInfo pcssTechnique() {
  std::vector<ParamSpec> params = shadowMapParams();
  // With its taps following the region, a finer map never loses (docs/techniques/sm-pcf-pcss.md, "Taps from the
  // region"): its error keeps falling until the narrow end of the penumbrae spans ~9 texels (6 before).
  paramNamed(params, "map-size-penumbra").defaultValue = 9;
  params.push_back(receiverPlaneParam());
  // auto (the default, 0): from each pixel's region, kernels/pcss.cl pcss_tap_count.
  ParamSpec searchTaps{"pcss-search-taps", 0, 1, 64,
                       fmt::format("Blocker search: taps x taps samples (grid) or taps^2 (disk); auto: {} per texel "
                                   "of each pixel's search disk, at least {}, at most pcss-search-taps-max^2",
                                   PCSS_SEARCH_DENSITY, PCSS_SEARCH_FEWEST)};
  ParamSpec filterTaps{"pcss-filter-taps", 0, 1, 64,
                       fmt::format("PCF: taps x taps (grid) or taps^2 (disk) bilinear comparisons; auto: {} per texel "
                                   "of each pixel's filter disk, at least {}, at most pcss-filter-taps-max^2",
                                   PCSS_FILTER_DENSITY, PCSS_FILTER_FEWEST)};
  searchTaps.autoName = filterTaps.autoName = "auto";
  params.push_back(searchTaps);
  params.push_back(filterTaps);
  params.push_back({"pcss-search-taps-max", 8, 1, 64, "pcss-search-taps auto: the most taps per side"});
  params.push_back({"pcss-filter-taps-max", 12, 1, 64, "pcss-filter-taps auto: the most taps per side"});
  params.push_back(kMaxRadius.param("pcss-max-radius", 1, 512, "Largest search/filter half-width in texels"));
  // The disk by default: at the grid's tap count it halves the grid's error or more, docs/techniques/sm-pcf-pcss.md.
  static_assert(SHADE_PATTERN_GRID == 0 && SHADE_PATTERN_POISSON == 1, "pcss-pattern's choices are SHADE_PATTERN_*");
  params.push_back({"pcss-pattern",
                    SHADE_PATTERN_POISSON,
                    0,
                    1,
                    "Search and filter taps: taps^2 rotated Poisson-disk points over the light's disk, or a taps x "
                    "taps grid over a square",
                    {"grid", "poisson"}});
  params.push_back({"pcss-search",
                    1,
                    0,
                    1,
                    "Blocker search region: the light's cone cut at the near plane (full), or narrowed by the nearest "
                    "caster in it from a min-max pyramid, lit without taps where nothing can block (adaptive)",
                    {"full", "adaptive"}});
  params.push_back({"pcss-umbra",
                    1,
                    0,
                    1,
                    "With --pcss-search adaptive: a pixel whose every search tap blocks is tested on the pyramid and "
                    "left at 0 without the filter's taps where every one of them must block (the same image; off: "
                    "every tap taken)",
                    {"off", "on"}});
  params.push_back({"pcss-stacked-trace",
                    1,
                    0,
                    1,
                    "Beyond the paper: a pixel whose search taps find blockers at several depths also traces its "
                    "segments to 32 light points through the map and keeps the darker result (stacked casters fuse, "
                    "where one average blocker depth lets light into the umbra)",
                    {"off", "on"}});
  params.push_back({"pcss-sparse-taps",
                    1,
                    0,
                    1,
                    "A filter whose taps each stand for 64 texels or more compares the texel under each tap instead "
                    "of four bilinearly (off: bilinear everywhere)",
                    {"off", "on"}});
  TechniqueInfo info{"pcss", "Percentage-closer soft shadows (blocker search + PCF) for area lights", params,
                     makeTechnique<PercentageCloserSoft>};
  // Its search and filter clamp at --pcss-max-radius: under auto a 32nd of the map's side, at least 64 texels.
  info.kernelReach = [](const Params& p, int size) { return kMaxRadius.texels(p, "pcss-max-radius", size); };
  return info;
}

}  // namespace penumbra
