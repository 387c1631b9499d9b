// SAT stage: summed-area tables of 1-, 2- or 4-channel float images by a tiled three-pass scan (Nehab et
// al. 2011; GPUs), line scans (CPUs) or Hensley et al. 2005 recursive doubling, stored as fp32 (offset to
// zero mean), 32- or 64-bit fixed point (exact, modular) or fp64. Box lookups: kernels/shared/sat.h.
// Precision by mode, size and filter width: docs/sat-precision.md.
#pragma once

#include <CL/opencl.hpp>
#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "host/cl/buffer.h"
#include "host/cl/context.h"
#include "host/stages/image_shape.h"
#include "kernels/shared/sat.h"

namespace penumbra {

// Auto: Tiled on GPUs and accelerators, Lines on CPUs (where barriers are loops and line scans vectorize
// across columns); Hensley is the textbook baseline.
enum class SatAlgorithm { Auto, Tiled, Lines, Hensley };

struct SatConfig {
  SatAlgorithm algorithm = SatAlgorithm::Auto;
  // Fixed point: values are stored as round(x * 2^fractionBits); -1 picks 16 (32-bit) or 32 (64-bit).
  // Box sums are exact while |sum| * 2^fractionBits < 2^31 (resp. 2^63).
  int fractionBits = -1;
  // fp32: subtract the per-channel mean of the finite texels (computed on the device, one extra read)
  // before summing, so that table values grow like sqrt(n) instead of n. Ignored by the other modes.
  bool zeroMean = true;
  std::optional<std::array<float, 4>> offset;  // fp32: a known offset instead of the mean (no extra read)
};

// The storage mode of element type T: float, uint32_t, uint64_t or double.
template <class T>
constexpr uint32_t satMode();
template <>
constexpr uint32_t satMode<float>() {
  return SAT_MODE_FP32;
}
template <>
constexpr uint32_t satMode<uint32_t>() {
  return SAT_MODE_FIXED32;
}
template <>
constexpr uint32_t satMode<uint64_t>() {
  return SAT_MODE_FIXED64;
}
template <>
constexpr uint32_t satMode<double>() {
  return SAT_MODE_FP64;
}

// The descriptor lookups need (kernels/shared/sat.h); throws std::invalid_argument on a bad shape or
// fraction-bit count.
SatTableDesc satDesc(const ImageShape& shape, uint32_t mode, int fractionBits = -1);

// The most fraction bits (at most 30 resp. 62) for which every box sum of up to `maxBoxTexels` texels with
// |value| <= maxAbsValue fits the signed word, so that lookups stay exact; throws std::invalid_argument
// when not even integers fit. E.g. 32-bit, values in [0, 1], boxes up to 255^2 texels: 15 bits.
int satFractionBits(uint32_t mode, double maxBoxTexels, double maxAbsValue);

// The algorithm `requested` runs as on `device` (Auto resolved by device class; computeSat further takes Lines
// for an Auto whose tiled kernels do not fit the device's local memory or work-group limits).
SatAlgorithm resolveSatAlgorithm(SatAlgorithm requested, const DeviceInfo& device);

// Whether the tiled scan's kernels for `desc` fit the device as `ctx` reports it (work-group size, local memory).
// Their __local tiles are static, SAT_TILE x (SAT_TILE + 1) texels plus a row of totals or segments (17 to 20.5 KiB
// for 4-channel fp32 and 32-bit tables, 34 to 41 KiB for 4-channel 64-bit ones), so a device of 16 or 32 KiB cannot
// tile every mode: Auto then scans lines (no local memory, the same table); an explicit Tiled fails its launch with
// CL_OUT_OF_RESOURCES naming the kernel and the bytes.
bool satTiledFits(Context& ctx, const SatTableDesc& desc);

// The -D options a kernel including kernels/shared/sat.h needs to read this table.
std::string satBuildOptions(const SatTableDesc& desc);

// Computes the table of `image` into `table` (shape.count() elements of T) and the fp32 offset into
// `offset` (4 floats; zeros for the other modes). Launch names "sat/sat_tile_sums", "sat/sat_carry",
// "sat/sat_tile_scan" (tiled), "sat/sat_lines_*" or "sat/sat_hensley_*", plus "sat/sat_mean_*" for the zero-mean
// offset. fp64 throws std::runtime_error on devices without it.
template <class T>
std::vector<cl::Event> computeSat(Context& ctx, const Buffer<float>& image, const ImageShape& shape, Buffer<T>& table,
                                  Buffer<float>& offset, const SatConfig& config = {});

}  // namespace penumbra
