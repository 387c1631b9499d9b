// The summed-area table, pyramid and Lloyd reduction stages on the caller's buffers (penumbra/stages.h over
// host/stages/sat.h, pyramid.h and reduce.h).
#include "api/stage_call.h"
#include "host/stages/pyramid.h"
#include "host/stages/reduce.h"
#include "host/stages/sat.h"

using penumbra::api::checkEnum;
using penumbra::api::guard;
using penumbra::api::require;
using penumbra::api::requireSized;
using penumbra::api::requireTexels;
using penumbra::api::StageCall;
using penumbra::api::stageShape;

static_assert(sizeof(pn_lloyd_stats) == sizeof(LloydStats) &&
                  offsetof(pn_lloyd_stats, samples) == offsetof(LloydStats, samples),
              "pn_lloyd_stats mirrors kernels/shared/reduce.h's LloydStats");
static_assert(sizeof(pn_pyramid_level) == sizeof(PyramidLevel), "pn_pyramid_level mirrors PyramidLevel");

namespace {

penumbra::SatConfig satConfig(const pn_sat_config& c, const char* function) {
  checkEnum(c.algorithm, 4, function, "SAT algorithm");
  const penumbra::SatAlgorithm algorithms[] = {penumbra::SatAlgorithm::Auto, penumbra::SatAlgorithm::Tiled,
                                               penumbra::SatAlgorithm::Lines, penumbra::SatAlgorithm::Hensley};
  penumbra::SatConfig config;
  config.algorithm = algorithms[c.algorithm];
  config.fractionBits = c.fraction_bits;
  config.zeroMean = c.zero_mean != 0;
  if (c.has_offset != 0) config.offset = std::array<float, 4>{c.offset[0], c.offset[1], c.offset[2], c.offset[3]};
  return config;
}

template <class T>
void satOf(StageCall& call, cl_mem image, const penumbra::ImageShape& shape, const penumbra::SatConfig& config,
           cl_mem table, cl_mem offset) {
  const auto in = call.input<float>(image, "image", shape.width, shape.height, shape.channels);
  auto out = call.buffer<T>(table, "table");
  auto mean = call.scratch<float>(offset, 4, "offset");
  penumbra::checkBufferSize(mean.size(), 4, call.function(), "offset");
  call.run([&] { penumbra::computeSat<T>(call.ctx(), in, shape, out, mean, config); });
}

uint32_t satMode(pn_sat_precision precision) {
  const uint32_t modes[] = {SAT_MODE_FP32, SAT_MODE_FIXED32, SAT_MODE_FIXED64, SAT_MODE_FP64};
  return modes[precision];
}

}  // namespace

extern "C" {

void pn_sat_config_init(pn_sat_config* config) {
  if (config == nullptr) return;
  const penumbra::SatConfig d;
  *config = pn_sat_config{sizeof(pn_sat_config), PN_SAT_FLOAT32, PN_SAT_AUTO, d.fractionBits, d.zeroMean ? 1 : 0, 0,
                          {0, 0, 0, 0}};
}

pn_status pn_sat(pn_context* context, cl_mem image, const pn_image_shape* shape, const pn_sat_config* config,
                 cl_mem table, cl_mem offset, cl_uint num_events_in_wait_list, const cl_event* event_wait_list,
                 cl_event* event) {
  return guard([&] {
    StageCall call(context, "pn_sat", num_events_in_wait_list, event_wait_list, event);
    const penumbra::ImageShape imageShape = stageShape(shape, call.function());
    const pn_sat_config& c =
        requireSized(config, sizeof(pn_sat_config), call.function(), "config", "pn_sat_config_init");
    checkEnum(c.precision, 4, call.function(), "SAT precision");
    const penumbra::SatConfig sat = satConfig(c, call.function());
    switch (c.precision) {
      case PN_SAT_FLOAT32:
        return satOf<float>(call, image, imageShape, sat, table, offset);
      case PN_SAT_FIXED32:
        return satOf<uint32_t>(call, image, imageShape, sat, table, offset);
      case PN_SAT_FIXED64:
        return satOf<uint64_t>(call, image, imageShape, sat, table, offset);
      case PN_SAT_FLOAT64:
        return satOf<double>(call, image, imageShape, sat, table, offset);
      case PN_SAT_PRECISION_MAX_ENUM:  // refused by checkEnum
        break;
    }
  });
}

pn_status pn_sat_fraction_bits(pn_sat_precision precision, double max_box_texels, double max_abs_value,
                               int* fraction_bits) {
  return guard([&] {
    checkEnum(precision, 4, "pn_sat_fraction_bits", "SAT precision");
    if (precision != PN_SAT_FIXED32 && precision != PN_SAT_FIXED64)
      throw std::invalid_argument("pn_sat_fraction_bits: fraction bits are for PN_SAT_FIXED32 and PN_SAT_FIXED64");
    *require(fraction_bits, "pn_sat_fraction_bits", "fraction_bits") =
        penumbra::satFractionBits(satMode(precision), max_box_texels, max_abs_value);
  });
}

pn_status pn_pyramid_layout(uint32_t width, uint32_t height, uint32_t first_level, pn_pyramid_level* levels,
                            size_t capacity, size_t* level_count, size_t* texels) {
  return guard([&] {
    requireTexels(width, height, "pn_pyramid_layout");
    if (capacity > 0) require(levels, "pn_pyramid_layout", "levels");
    const penumbra::PyramidLayout layout = penumbra::pyramidLayout(width, height, first_level);
    for (size_t i = 0; i < layout.levels.size() && i < capacity; ++i) {
      const PyramidLevel& level = layout.levels[i];
      levels[i] = pn_pyramid_level{level.offset, level.width, level.height, 0};
    }
    if (level_count != nullptr) *level_count = layout.levels.size();
    if (texels != nullptr) *texels = layout.texels;
  });
}

pn_status pn_moment_mips(pn_context* context, cl_mem base, const pn_image_shape* shape, pn_moment_storage storage,
                         cl_mem mips, cl_uint num_events_in_wait_list, const cl_event* event_wait_list,
                         cl_event* event) {
  return guard([&] {
    StageCall call(context, "pn_moment_mips", num_events_in_wait_list, event_wait_list, event);
    const penumbra::ImageShape s = stageShape(shape, call.function());
    checkEnum(storage, 2, call.function(), "moment storage");
    if (storage == PN_STORAGE_FLOAT16) {
      const auto in = call.input<cl_half>(base, "base", s.width, s.height, s.channels);
      auto out = call.buffer<cl_half>(mips, "mips");
      call.run([&] { penumbra::computeMomentMips(call.ctx(), in, s, out); });
    } else {
      const auto in = call.input<float>(base, "base", s.width, s.height, s.channels);
      auto out = call.buffer<float>(mips, "mips");
      call.run([&] { penumbra::computeMomentMips(call.ctx(), in, s, out); });
    }
  });
}

pn_status pn_minmax_pyramid(pn_context* context, cl_mem depth, uint32_t width, uint32_t height, cl_mem out,
                            cl_uint num_events_in_wait_list, const cl_event* event_wait_list, cl_event* event) {
  return guard([&] {
    StageCall call(context, "pn_minmax_pyramid", num_events_in_wait_list, event_wait_list, event);
    requireTexels(width, height, call.function());
    const auto in = call.input<float>(depth, "depth", width, height, 1);
    auto target = call.buffer<cl_float2>(out, "out");
    call.run([&] { penumbra::computeMinMaxPyramid(call.ctx(), in, width, height, target); });
  });
}

pn_status pn_lloyd_stats_reduce(pn_context* context, cl_mem x, cl_mem w, size_t count, cl_mem boundaries,
                                uint32_t clusters, cl_mem out, cl_uint num_events_in_wait_list,
                                const cl_event* event_wait_list, cl_event* event) {
  return guard([&] {
    StageCall call(context, "pn_lloyd_stats_reduce", num_events_in_wait_list, event_wait_list, event);
    const auto xs = call.buffer<float>(x, "x");
    const auto ws = call.buffer<float>(w, "w");
    // One cluster has no boundaries: NULL stands for an empty list.
    const auto bounds = clusters == 1 && boundaries == nullptr ? penumbra::Buffer<float>(call.ctx(), 0)
                                                               : call.buffer<float>(boundaries, "boundaries");
    auto stats = call.buffer<LloydStats>(out, "out");
    call.run([&] { penumbra::reduceLloydStats(call.ctx(), xs, ws, count, bounds, clusters, stats); });
  });
}

}  // extern "C"
