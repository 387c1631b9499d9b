// SAT stage host wrapper: plans the storage mode and scratch, computes the fp32 offset, then records the
// tiled passes (tile sums, carries, tile scan) or Hensley's ping-pong passes.
#include "host/stages/sat.h"

#include <fmt/format.h>

#include <bit>
#include <cmath>
#include <stdexcept>

#include "host/cl/kernel.h"

namespace penumbra {
namespace {

constexpr uint32_t kMeanChunkTexels = 16 * SAT_REDUCE_GROUP;  // texels per mean work-group at least

uint32_t ceilDiv(uint32_t a, uint32_t b) { return (a + b - 1) / b; }

// The fp32 offset (the mean, an explicit value or zero) into `offset`.
void computeOffset(Context& ctx, const std::string& options, const Buffer<float>& image, const ImageShape& shape,
                   uint32_t mode, const SatConfig& config, Buffer<float>& offset, std::vector<cl::Event>& events) {
  if (mode != SAT_MODE_FP32 || (!config.zeroMean && !config.offset)) {
    offset.fill(ctx, 0.0f);
    return;
  }
  if (config.offset) {
    offset.copyFrom(ctx, Buffer<float>::copyOf(ctx, *config.offset));  // no blocking write: stages never wait
    return;
  }
  const uint32_t texels = static_cast<uint32_t>(shape.texels());
  const uint32_t groups = std::min<uint32_t>(1024, ceilDiv(texels, kMeanChunkTexels));
  const uint32_t chunk = ceilDiv(texels, groups);
  Buffer<float> partials(ctx, size_t(groups) * 8);
  Kernel partial(ctx, "kernels/sat.cl", "sat_mean_partial", "sat", options);
  events.push_back(partial.args(image, texels, chunk, partials)
                       .moves(image.bytes())
                       .launch(size_t(groups) * SAT_REDUCE_GROUP, SAT_REDUCE_GROUP));
  Kernel finish(ctx, "kernels/sat.cl", "sat_mean_final", "sat", options);
  events.push_back(finish.args(partials, groups, offset).launch(SAT_REDUCE_GROUP, SAT_REDUCE_GROUP));
}

template <class T>
void tiled(Context& ctx, const std::string& options, const Buffer<float>& image, const SatTableDesc& d,
           const Buffer<float>& offset, Buffer<T>& table, std::vector<cl::Event>& events) {
  const size_t c = d.channels;
  Buffer<T> rowSums(ctx, size_t(d.height) * d.tilesX * c), colSums(ctx, size_t(d.tilesY) * d.width * c);
  Buffer<T> totals(ctx, size_t(d.tilesY) * d.tilesX * c);
  const Range tiles(size_t(d.tilesX) * SAT_TILE, size_t(d.tilesY) * SAT_GROUP_Y), group(SAT_TILE, SAT_GROUP_Y);
  Kernel sums(ctx, "kernels/sat.cl", "sat_tile_sums", "sat", options);
  // Floors: the sums read the image once; the scan reads it again and writes the table once.
  const uint64_t values = uint64_t{d.width} * d.height * c, imageBytes = values * sizeof(float);
  const uint64_t tableBytes = values * sizeof(T);
  events.push_back(sums.args(image, d, offset, rowSums, colSums, totals).moves(imageBytes).launch(tiles, group));
  Kernel carry(ctx, "kernels/sat.cl", "sat_carry", "sat", options);
  const size_t carryGroups = ceilDiv(d.width + d.height, SAT_CARRY_GROUP) + 1;  // + the corner work-group
  events.push_back(carry.args(d, rowSums, colSums, totals).launch(carryGroups * SAT_CARRY_GROUP, SAT_CARRY_GROUP));
  Kernel scan(ctx, "kernels/sat.cl", "sat_tile_scan", "sat", options);
  events.push_back(
      scan.args(image, d, offset, rowSums, colSums, totals, table).moves(imageBytes + tableBytes).launch(tiles, group));
}

template <class T>
void lines(Context& ctx, const std::string& options, const Buffer<float>& image, const SatTableDesc& d,
           const Buffer<float>& offset, Buffer<T>& table, std::vector<cl::Event>& events) {
  Kernel rows(ctx, "kernels/sat.cl", "sat_lines_rows", "sat", options);
  // Floors: rows read the image and write the table; columns read and write the table.
  const uint64_t values = uint64_t{d.width} * d.height * d.channels, imageBytes = values * sizeof(float);
  const uint64_t tableBytes = values * sizeof(T);
  events.push_back(rows.args(image, d, offset, table).moves(imageBytes + tableBytes).launch(d.height, 16));
  Kernel columns(ctx, "kernels/sat.cl", "sat_lines_columns", "sat", options);
  events.push_back(columns.args(d, table).moves(2 * tableBytes).launch(ceilDiv(d.width, SAT_LINE_BLOCK), 1));
}

template <class T>
void hensley(Context& ctx, const std::string& options, const Buffer<float>& image, const SatTableDesc& d,
             const Buffer<float>& offset, Buffer<T>& table, std::vector<cl::Event>& events) {
  Buffer<T> temp(ctx, size_t(d.width) * d.height * d.channels);
  const uint32_t rowPasses = std::bit_width(d.width - 1), columnPasses = std::bit_width(d.height - 1);
  const uint32_t passes = 1 + rowPasses + columnPasses;
  auto target = [&](uint32_t pass) -> Buffer<T>& { return (passes - 1 - pass) % 2 == 0 ? table : temp; };
  Kernel load(ctx, "kernels/sat.cl", "sat_hensley_load", "sat", options);
  // Floors: the load reads the image and writes a table; each doubling pass reads one table and writes the other.
  const uint64_t values = uint64_t{d.width} * d.height * d.channels, imageBytes = values * sizeof(float);
  const uint64_t tableBytes = values * sizeof(T);
  events.push_back(
      load.args(image, d, offset, target(0)).moves(imageBytes + tableBytes).launch(size_t(d.width) * d.height, 64));
  Kernel rows(ctx, "kernels/sat.cl", "sat_hensley_rows", "sat", options);
  Kernel columns(ctx, "kernels/sat.cl", "sat_hensley_columns", "sat", options);
  for (uint32_t pass = 1; pass < passes; ++pass) {
    const bool alongRows = pass <= rowPasses;
    const uint32_t step = 1u << (alongRows ? pass - 1 : pass - 1 - rowPasses);
    Kernel& k = alongRows ? rows : columns;
    events.push_back(k.args(target(pass - 1), target(pass), d, step)
                         .moves(2 * tableBytes)
                         .launch(Range(d.width, d.height), Range(32, 4)));
  }
}

}  // namespace

SatTableDesc satDesc(const ImageShape& shape, uint32_t mode, int fractionBits) {
  checkShape(shape, "sat");
  SatTableDesc d{};
  d.width = shape.width;
  d.height = shape.height;
  d.channels = shape.channels;
  d.mode = mode;
  d.tilesX = ceilDiv(shape.width, SAT_TILE);
  d.tilesY = ceilDiv(shape.height, SAT_TILE);
  int bits = 0;
  if (mode == SAT_MODE_FIXED32 || mode == SAT_MODE_FIXED64) {
    const int maxBits = mode == SAT_MODE_FIXED32 ? 30 : 62;
    bits = fractionBits < 0 ? (mode == SAT_MODE_FIXED32 ? 16 : 32) : fractionBits;
    if (bits > maxBits) throw std::invalid_argument(fmt::format("sat: {} fraction bits (at most {})", bits, maxBits));
  }
  d.scale = std::ldexp(1.0f, bits);
  d.invScale = std::ldexp(1.0f, -bits);
  return d;
}

int satFractionBits(uint32_t mode, double maxBoxTexels, double maxAbsValue) {
  if (mode != SAT_MODE_FIXED32 && mode != SAT_MODE_FIXED64)
    throw std::invalid_argument("sat: fraction bits apply to fixed-point modes only");
  const int maxBits = mode == SAT_MODE_FIXED32 ? 30 : 62;
  const double limit = mode == SAT_MODE_FIXED32 ? 2147483647.0 : 9223372036854775807.0;
  for (int bits = maxBits; bits >= 0; --bits)  // each texel rounds by at most 1/2
    if (maxBoxTexels * (std::ldexp(maxAbsValue, bits) + 0.5) <= limit) return bits;
  throw std::invalid_argument(fmt::format("sat: box sums of {} texels of magnitude {} overflow even integer storage",
                                          maxBoxTexels, maxAbsValue));
}

SatAlgorithm resolveSatAlgorithm(SatAlgorithm requested, const DeviceInfo& device) {
  if (requested != SatAlgorithm::Auto) return requested;
  return device.cpuLayouts() ? SatAlgorithm::Lines : SatAlgorithm::Tiled;
}

bool satTiledFits(Context& ctx, const SatTableDesc& desc) {
  const std::string options = satBuildOptions(desc);
  const Range group(SAT_TILE, SAT_GROUP_Y);
  return Kernel(ctx, "kernels/sat.cl", "sat_tile_sums", "sat", options).fits(group) &&
         Kernel(ctx, "kernels/sat.cl", "sat_tile_scan", "sat", options).fits(group) &&
         Kernel(ctx, "kernels/sat.cl", "sat_carry", "sat", options).fits(SAT_CARRY_GROUP);
}

std::string satBuildOptions(const SatTableDesc& desc) {
  return fmt::format("-DSAT_MODE={} -DSAT_CHANNELS={}", desc.mode, desc.channels);
}

template <class T>
std::vector<cl::Event> computeSat(Context& ctx, const Buffer<float>& image, const ImageShape& shape, Buffer<T>& table,
                                  Buffer<float>& offset, const SatConfig& config) {
  constexpr uint32_t mode = satMode<T>();
  const SatTableDesc desc = satDesc(shape, mode, config.fractionBits);
  if (mode == SAT_MODE_FP64 && !ctx.info().fp64)
    throw std::runtime_error(fmt::format("sat: fp64 tables need cl_khr_fp64, which {} lacks", ctx.info().name));
  checkBufferSize(image.size(), shape.count(), "sat", "image");
  checkBufferSize(table.size(), shape.count(), "sat", "table");
  checkBufferSize(offset.size(), 4, "sat", "offset");
  std::vector<cl::Event> events;
  if (shape.texels() == 0) return events;
  const std::string options = satBuildOptions(desc);
  computeOffset(ctx, options, image, shape, mode, config, offset, events);
  SatAlgorithm algorithm = resolveSatAlgorithm(config.algorithm, ctx.info());
  if (config.algorithm == SatAlgorithm::Auto && algorithm == SatAlgorithm::Tiled && !satTiledFits(ctx, desc))
    algorithm = SatAlgorithm::Lines;
  switch (algorithm) {
    case SatAlgorithm::Lines:
      lines(ctx, options, image, desc, offset, table, events);
      break;
    case SatAlgorithm::Hensley:
      hensley(ctx, options, image, desc, offset, table, events);
      break;
    default:
      tiled(ctx, options, image, desc, offset, table, events);
      break;
  }
  return events;
}

template std::vector<cl::Event> computeSat(Context&, const Buffer<float>&, const ImageShape&, Buffer<float>&,
                                           Buffer<float>&, const SatConfig&);
template std::vector<cl::Event> computeSat(Context&, const Buffer<float>&, const ImageShape&, Buffer<uint32_t>&,
                                           Buffer<float>&, const SatConfig&);
template std::vector<cl::Event> computeSat(Context&, const Buffer<float>&, const ImageShape&, Buffer<uint64_t>&,
                                           Buffer<float>&, const SatConfig&);
template std::vector<cl::Event> computeSat(Context&, const Buffer<float>&, const ImageShape&, Buffer<double>&,
                                           Buffer<float>&, const SatConfig&);

}  // namespace penumbra
