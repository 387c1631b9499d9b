// Moments stage host wrapper: validates the configuration, fills MomentsParams and launches the kernel of
// the requested encoding over one work-item per texel.
#include "host/stages/moments.h"

#include <fmt/format.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <stdexcept>

#include "host/cl/kernel.h"
#include "host/stages/image_shape.h"

namespace penumbra {
namespace {

const char* entryPoint(MomentKind kind) {
  switch (kind) {
    case MomentKind::Vsm:
      return "moments_vsm";
    case MomentKind::Esm:
      return "moments_esm";
    case MomentKind::Evsm2:
      return "moments_evsm2";
    case MomentKind::Evsm4:
      return "moments_evsm4";
    case MomentKind::Lvsm:
      return "moments_lvsm";
    case MomentKind::Msm:
      return "moments_msm";
  }
  throw std::invalid_argument("moments: unknown moment kind");
}

void validate(const MomentsConfig& config) {
  if (!std::isfinite(config.depthNear) || !std::isfinite(config.depthFar) || !(config.depthFar > config.depthNear))
    throw std::invalid_argument(
        fmt::format("moments: depth range [{}, {}] must be finite with far > near", config.depthNear, config.depthFar));
  if (config.kind != MomentKind::Lvsm) return;
  if (config.layers.empty() || config.layers.size() > MOMENTS_MAX_LAYERS)
    throw std::invalid_argument(
        fmt::format("moments: {} LVSM layers (1..{})", config.layers.size(), MOMENTS_MAX_LAYERS));
  for (size_t i = 0; i < config.layers.size(); ++i)
    if (!(config.layers[i].q > config.layers[i].p))
      throw std::invalid_argument(
          fmt::format("moments: LVSM layer {} has q {} <= p {}", i, config.layers[i].q, config.layers[i].p));
}

}  // namespace

std::string storageOptions(MomentStorage storage) { return storage == MomentStorage::Float16 ? "-DSTORE_HALF" : ""; }

void checkHalfMoments(const MomentsConfig& config, const char* stage) {
  if (config.storage != MomentStorage::Float16)
    throw std::invalid_argument(
        fmt::format("{}: half moments need MomentStorage::Float16 (EVSM exponents bounded by half)", stage));
}

float evsmMaxExponent(MomentStorage storage) {
  return storage == MomentStorage::Float16 ? MOMENTS_EVSM_MAX_EXPONENT_FP16 : MOMENTS_EVSM_MAX_EXPONENT_FP32;
}

namespace {
float clampExponent(float exponent, float max) { return std::isnan(exponent) ? 0.0f : std::clamp(exponent, 0.0f, max); }
}  // namespace

float evsmClampExponent(float exponent, MomentStorage storage) {
  return clampExponent(exponent, evsmMaxExponent(storage));
}

float esmMaxExponent(MomentStorage storage) {
  return storage == MomentStorage::Float16 ? MOMENTS_ESM_MAX_EXPONENT_FP16 : MOMENTS_ESM_MAX_EXPONENT_FP32;
}

float esmClampExponent(float exponent, MomentStorage storage) {
  return clampExponent(exponent, esmMaxExponent(storage));
}

bool esmLogSpace(float exponent) {
  return !(exponent >= MOMENTS_ESM_LINEAR_MIN_EXPONENT && exponent <= MOMENTS_ESM_LINEAR_EXPONENT);
}

uint32_t momentChannels(MomentKind kind) {
  if (kind == MomentKind::Esm) return 1;
  return kind == MomentKind::Evsm4 || kind == MomentKind::Msm ? 4 : 2;
}

uint32_t momentPlanes(const MomentsConfig& config) {
  return config.kind == MomentKind::Lvsm ? static_cast<uint32_t>(config.layers.size()) : 1;
}

MomentsParams momentsParams(const MomentsConfig& config, uint32_t width, uint32_t height) {
  validate(config);
  checkShape({width, height, 1}, "moments");
  MomentsParams params{};
  params.width = width;
  params.height = height;
  params.layerCount = momentPlanes(config);
  params.depthNear = config.depthNear;
  params.depthInvRange = 1.0f / (config.depthFar - config.depthNear);
  params.expPositive = evsmClampExponent(config.evsmPositive, config.storage);
  if (config.kind == MomentKind::Esm) {
    params.expPositive = esmClampExponent(config.esmExponent, config.storage);
    params.esmLogSpace = esmLogSpace(params.expPositive) ? 1u : 0u;
  }
  params.expNegative = evsmClampExponent(config.evsmNegative, config.storage);
  params.pitch = width;
  if (!std::isfinite(params.depthInvRange)) throw std::invalid_argument("moments: depth range too small for fp32");
  return params;
}

TexelWindow windowOf(const TexelWindow& window, uint32_t width, uint32_t height) {
  if (window.width == 0) return {0, 0, width, height};
  if (window.height == 0 || window.x >= width || window.y >= height || window.width > width - window.x ||
      window.height > height - window.y)
    throw std::invalid_argument(fmt::format("moments: window {}x{} at ({}, {}) outside the {}x{} map", window.width,
                                            window.height, window.x, window.y, width, height));
  return window;
}

int momentsKindId(MomentKind kind) {
  switch (kind) {
    case MomentKind::Vsm:
      return MOMENTS_KIND_VSM;
    case MomentKind::Esm:
      return MOMENTS_KIND_ESM;
    case MomentKind::Evsm2:
      return MOMENTS_KIND_EVSM2;
    case MomentKind::Evsm4:
      return MOMENTS_KIND_EVSM4;
    case MomentKind::Msm:
      return MOMENTS_KIND_MSM;
    case MomentKind::Lvsm:
      break;
  }
  throw std::invalid_argument("moments: LVSM has one plane per layer, not a single-plane encoding");
}

namespace {

// momentsParams over `window` of the map: its size, read from its origin in rows of the map's width.
MomentsParams windowParams(const MomentsConfig& config, uint32_t width, uint32_t height, const TexelWindow& window) {
  MomentsParams params = momentsParams(config, width, height);
  params.width = window.width, params.height = window.height;
  params.originX = window.x, params.originY = window.y;
  return params;
}

// Moments of `depth` into `out`, whose element type is the storage (float, or cl_half built with STORE_HALF).
template <class T>
cl::Event launchMoments(Context& ctx, const Buffer<float>& depth, uint32_t width, uint32_t height,
                        const MomentsConfig& config, Buffer<T>& out, const TexelWindow& area) {
  if (area.width != 0 && config.kind == MomentKind::Lvsm)
    throw std::invalid_argument("moments: LVSM layers cover the whole map (no window)");
  const TexelWindow window = windowOf(area, width, height);
  const MomentsParams params = windowParams(config, width, height, window);
  checkBufferSize(depth.size(), size_t(width) * height, "moments", "depth");
  const size_t texels = size_t(window.width) * window.height;
  checkBufferSize(out.size(), texels * momentChannels(config.kind) * momentPlanes(config), "moments", "output");

  Kernel kernel(ctx, "kernels/moments.cl", entryPoint(config.kind), "moments", storageOptions(storageOf<T>()));
  const Range global(window.width, window.height), local(16, 8);
  // Floor: read each depth texel and write each moment once.
  const uint64_t bytes = texels * (sizeof(float) + momentChannels(config.kind) * momentPlanes(config) * sizeof(T));
  if (config.kind != MomentKind::Lvsm) return kernel.args(depth, out, params).moves(bytes).launch(global, local);

  std::vector<cl_float2> layers(config.layers.size());
  for (size_t i = 0; i < layers.size(); ++i) layers[i] = {{config.layers[i].p, config.layers[i].q}};
  Buffer<cl_float2> layerBuffer = Buffer<cl_float2>::copyOf(ctx, layers);
  return kernel.args(depth, out, layerBuffer, params).moves(bytes).launch(global, local);
}

}  // namespace

cl::Event computeMoments(Context& ctx, const Buffer<float>& depth, uint32_t width, uint32_t height,
                         const MomentsConfig& config, Buffer<float>& out, const TexelWindow& window) {
  return launchMoments(ctx, depth, width, height, config, out, window);
}

cl::Event computeMoments(Context& ctx, const Buffer<float>& depth, uint32_t width, uint32_t height,
                         const MomentsConfig& config, Buffer<cl_half>& out) {
  if (config.kind == MomentKind::Lvsm)
    throw std::invalid_argument("moments: LVSM layers are fp32 or unorm16, not half");
  checkHalfMoments(config, "moments");
  return launchMoments(ctx, depth, width, height, config, out, TexelWindow{});
}

uint32_t reducedExtent(uint32_t extent, uint32_t factor) {
  if (factor == 0) throw std::invalid_argument("moments: a reduction factor of 0");
  return extent / factor + (extent % factor != 0 ? 1 : 0);
}

cl::Event computeMomentsReduced(Context& ctx, const Buffer<float>& depth, uint32_t width, uint32_t height,
                                const MomentsConfig& config, uint32_t factor, Buffer<float>& out,
                                const TexelWindow& area) {
  if (factor < 1 || factor > kMaxMomentsReduction)
    throw std::invalid_argument(
        fmt::format("moments: reduction factor {} outside 1..{}", factor, kMaxMomentsReduction));
  if (config.kind == MomentKind::Lvsm)
    throw std::invalid_argument("moments: LVSM layers are not reduced (one plane per layer)");
  if (config.storage != MomentStorage::Float32) throw std::invalid_argument("moments: reduced moments are fp32");
  const TexelWindow window = windowOf(area, width, height);
  const MomentsParams params = windowParams(config, width, height, window);
  if (config.kind == MomentKind::Esm && params.esmLogSpace != 0)
    throw std::invalid_argument(
        fmt::format("moments: ESM with exponent {} is filtered in log space, which a block mean does not reduce",
                    params.expPositive));
  const uint32_t outWidth = reducedExtent(window.width, factor), outHeight = reducedExtent(window.height, factor);
  const size_t texels = size_t(window.width) * window.height, outTexels = size_t(outWidth) * outHeight;
  checkBufferSize(depth.size(), size_t(width) * height, "moments", "depth");
  checkBufferSize(out.size(), outTexels * momentChannels(config.kind), "moments", "output");
  // Floor: read each depth texel once, write each block's moments once.
  const uint64_t bytes = texels * sizeof(float) + outTexels * momentChannels(config.kind) * sizeof(float);
  if (config.kind == MomentKind::Vsm && factor == 2 && ctx.info().cpuLayouts()) {  // 8 blocks per work-item
    Kernel rows(ctx, "kernels/moments.cl", "moments_vsm_reduced2_rows", "moments");
    const uint32_t items = (outWidth + 7) / 8;
    return rows.args(depth, out, params)
        .moves(bytes)
        .launch(Range(items, outHeight), Range(std::min<uint32_t>(32, std::bit_ceil(items)), 1));
  }
  Kernel kernel(ctx, "kernels/moments.cl", fmt::format("{}_reduced", entryPoint(config.kind)), "moments");
  return kernel.args(depth, out, params, factor).moves(bytes).launch(Range(outWidth, outHeight), Range(128, 1));
}

cl::Event packMomentsUnorm16(Context& ctx, const Buffer<float>& in, size_t count, Buffer<cl_ushort>& out,
                             size_t outOffset) {
  checkBufferSize(in.size(), count, "moments", "unorm16 input");
  checkBufferSize(out.size(), outOffset + count, "moments", "unorm16 output");
  if (outOffset + count > UINT32_MAX) throw std::invalid_argument("moments: unorm16 output above 2^32 elements");
  Kernel kernel(ctx, "kernels/moments.cl", "moments_pack_unorm16", "moments");
  return kernel.args(in, out, static_cast<uint32_t>(count), static_cast<uint32_t>(outOffset))
      .moves(uint64_t{count} * (sizeof(float) + sizeof(uint16_t)))  // fp32 in, unorm16 out
      .launch(count, 64);
}

cl::Event packMomentsHalf(Context& ctx, const Buffer<float>& in, size_t count, Buffer<cl_half>& out) {
  checkBufferSize(in.size(), count, "moments", "half input");
  checkBufferSize(out.size(), count, "moments", "half output");
  if (count > UINT32_MAX) throw std::invalid_argument("moments: half output above 2^32 elements");
  Kernel kernel(ctx, "kernels/moments.cl", "moments_pack_half", "moments");
  return kernel.args(in, out, static_cast<uint32_t>(count))
      .moves(uint64_t{count} * (sizeof(float) + sizeof(cl_half)))  // fp32 in, half out
      .launch(count, 64);
}

}  // namespace penumbra
