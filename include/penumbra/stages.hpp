// penumbra's C++ API: the filtering stages on the caller's cl_mem buffers (penumbra/stages.h), CLBlast-style: a wait
// list in, an event out (owned by the caller), nothing finished or released behind the caller's back.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <vector>

#include "penumbra/context.hpp"
#include "penumbra/error.hpp"
#include "penumbra/stages.h"

/// @file
/// penumbra::moments, blur, blurMoments, sat, momentMips, minMaxPyramid, lloydStats, imageCopy.

namespace penumbra {
inline namespace v0 {

/// width x height texels of `channels` interleaved floats (1, 2 or 4).
struct ImageShape {
  uint32_t width = 0;     ///< Texels per row.
  uint32_t height = 0;    ///< Rows.
  uint32_t channels = 1;  ///< 1, 2 or 4.
  /// As the C API takes it.
  pn_image_shape toC() const { return {width, height, channels}; }
};

/// Moment encodings (pn_moment_kind).
enum class MomentKind {
  Vsm = PN_MOMENTS_VSM,
  Evsm2 = PN_MOMENTS_EVSM2,
  Evsm4 = PN_MOMENTS_EVSM4,
  Lvsm = PN_MOMENTS_LVSM,
  Msm = PN_MOMENTS_MSM,
  Esm = PN_MOMENTS_ESM
};
/// Moment element types (pn_moment_storage).
enum class MomentStorage { Float32 = PN_STORAGE_FLOAT32, Float16 = PN_STORAGE_FLOAT16 };

/// One LVSM layer: the normalised depth interval [p, q].
struct LvsmLayer {
  float p = 0.0f;  ///< Start.
  float q = 1.0f;  ///< End (> p).
};

/// The moments stage's settings (pn_moments_config; the same defaults).
struct MomentsConfig {
  MomentKind kind = MomentKind::Vsm;               ///< Encoding.
  float depthNear = 0.0f;                          ///< Light depth mapped to 0.
  float depthFar = 1.0f;                           ///< Light depth mapped to 1.
  float evsmPositive = 40.0f;                      ///< EVSM positive exponent (clamped to the storage).
  float evsmNegative = 5.0f;                       ///< EVSM negative exponent (clamped likewise).
  MomentStorage storage = MomentStorage::Float32;  ///< Output element type.
  std::vector<LvsmLayer> layers;                   ///< LVSM only.
  float esmExponent = 80.0f;                       ///< ESM's c of e^(c z) (log-space filters outside [1, 80]).
  /// As the C API takes it; its layers point into this config.
  pn_moments_config toC() const {
    static_assert(sizeof(LvsmLayer) == sizeof(pn_lvsm_layer), "LvsmLayer mirrors pn_lvsm_layer");
    pn_moments_config c;
    pn_moments_config_init(&c);
    c.kind = static_cast<pn_moment_kind>(kind);
    c.depth_near = depthNear, c.depth_far = depthFar;
    c.evsm_positive = evsmPositive, c.evsm_negative = evsmNegative;
    c.storage = static_cast<pn_moment_storage>(storage);
    c.layers = reinterpret_cast<const pn_lvsm_layer*>(layers.data()), c.layer_count = layers.size();
    c.esm_exponent = esmExponent;
    return c;
  }
};

/// Blur filters (pn_blur_filter).
enum class BlurFilter { Gaussian = PN_BLUR_GAUSSIAN, Box = PN_BLUR_BOX };
/// Blur methods (pn_blur_method).
enum class BlurMethod { Auto = PN_BLUR_AUTO, Direct = PN_BLUR_DIRECT, RunningSums = PN_BLUR_RUNNING_SUMS };

/// The blur's settings (pn_blur_config; the same defaults).
struct BlurConfig {
  BlurFilter filter = BlurFilter::Gaussian;  ///< Gaussian or box.
  float sigma = 1.0f;                        ///< Gaussian standard deviation, texels.
  int radius = 1;                            ///< Box half-width, texels.
  BlurMethod method = BlurMethod::Auto;      ///< How it runs.
  /// As the C API takes it.
  pn_blur_config toC() const {
    pn_blur_config c;
    pn_blur_config_init(&c);
    c.filter = static_cast<pn_blur_filter>(filter), c.sigma = sigma, c.radius = radius;
    c.method = static_cast<pn_blur_method>(method);
    return c;
  }
};

/// SAT element types (pn_sat_precision): float, uint32_t, uint64_t, double.
enum class SatPrecision {
  Float32 = PN_SAT_FLOAT32,
  Fixed32 = PN_SAT_FIXED32,
  Fixed64 = PN_SAT_FIXED64,
  Float64 = PN_SAT_FLOAT64
};
/// SAT scans (pn_sat_algorithm).
enum class SatAlgorithm { Auto = PN_SAT_AUTO, Tiled = PN_SAT_TILED, Lines = PN_SAT_LINES, Hensley = PN_SAT_HENSLEY };

/// The SAT's settings (pn_sat_config; the same defaults).
struct SatConfig {
  SatPrecision precision = SatPrecision::Float32;  ///< Table element type.
  SatAlgorithm algorithm = SatAlgorithm::Auto;     ///< Scan.
  int fractionBits = -1;                           ///< Fixed point: -1 for 16 (fixed32) or 32 (fixed64).
  bool zeroMean = true;                            ///< fp32: subtract the mean first.
  std::optional<std::array<float, 4>> offset;      ///< fp32: subtract this instead of the mean.
  /// As the C API takes it.
  pn_sat_config toC() const {
    pn_sat_config c;
    pn_sat_config_init(&c);
    c.precision = static_cast<pn_sat_precision>(precision), c.algorithm = static_cast<pn_sat_algorithm>(algorithm);
    c.fraction_bits = fractionBits, c.zero_mean = zeroMean ? 1 : 0, c.has_offset = offset ? 1 : 0;
    if (offset)
      for (int i = 0; i < 4; ++i) c.offset[i] = (*offset)[i];
    return c;
  }
};

/// A pyramid's levels and its buffer's size in texels (pn_pyramid_layout).
struct PyramidLayout {
  std::vector<pn_pyramid_level> levels;  ///< Offset (texels), width, height of each level.
  size_t texels = 0;                     ///< Texels of the whole buffer.
};

/// Per-cluster Lloyd statistics, laid out as pn_lloyd_stats.
using LloydStats = pn_lloyd_stats;

namespace detail {
inline const cl_event* waitList(const std::vector<cl_event>& events) {
  return events.empty() ? nullptr : events.data();
}
inline cl_uint waitCount(const std::vector<cl_event>& events) { return static_cast<cl_uint>(events.size()); }
}  // namespace detail

/// Moments of `depth` into `out` (pn_moments).
inline void moments(const Context& context, cl_mem depth, uint32_t width, uint32_t height, const MomentsConfig& config,
                    cl_mem out, const std::vector<cl_event>& waitFor = {}, cl_event* event = nullptr) {
  const pn_moments_config c = config.toC();
  detail::check(pn_moments(context.get(), depth, width, height, &c, out, detail::waitCount(waitFor),
                           detail::waitList(waitFor), event));
}

/// Blurs `in` into `out` (pn_blur); `scratch` nullptr for a temporary.
inline void blur(const Context& context, cl_mem in, cl_mem out, const ImageShape& shape, const BlurConfig& config = {},
                 const std::vector<cl_event>& waitFor = {}, cl_event* event = nullptr, cl_mem scratch = nullptr) {
  const pn_image_shape s = shape.toC();
  const pn_blur_config c = config.toC();
  detail::check(
      pn_blur(context.get(), in, out, scratch, &s, &c, detail::waitCount(waitFor), detail::waitList(waitFor), event));
}

/// Blurred moments of `depth` into `out` (pn_blur_moments).
inline void blurMoments(const Context& context, cl_mem depth, uint32_t width, uint32_t height,
                        const MomentsConfig& moments, const BlurConfig& blur, cl_mem out,
                        const std::vector<cl_event>& waitFor = {}, cl_event* event = nullptr,
                        cl_mem scratch = nullptr) {
  const pn_moments_config m = moments.toC();
  const pn_blur_config b = blur.toC();
  detail::check(pn_blur_moments(context.get(), depth, width, height, &m, &b, out, scratch, detail::waitCount(waitFor),
                                detail::waitList(waitFor), event));
}

/// Floats of scratch blurMoments needs (pn_blur_moments_scratch).
inline size_t blurMomentsScratch(const Context& context, uint32_t width, uint32_t height, const MomentsConfig& moments,
                                 const BlurConfig& blur) {
  const pn_moments_config m = moments.toC();
  const pn_blur_config b = blur.toC();
  size_t floats = 0;
  detail::check(pn_blur_moments_scratch(context.get(), width, height, &m, &b, &floats));
  return floats;
}

/// The summed-area table of `image` into `table`, the fp32 offset into `offset` (pn_sat; nullptr: not kept).
inline void sat(const Context& context, cl_mem image, const ImageShape& shape, const SatConfig& config, cl_mem table,
                cl_mem offset = nullptr, const std::vector<cl_event>& waitFor = {}, cl_event* event = nullptr) {
  const pn_image_shape s = shape.toC();
  const pn_sat_config c = config.toC();
  detail::check(pn_sat(context.get(), image, &s, &c, table, offset, detail::waitCount(waitFor),
                       detail::waitList(waitFor), event));
}

/// The most fraction bits that keep box sums exact (pn_sat_fraction_bits).
inline int satFractionBits(SatPrecision precision, double maxBoxTexels, double maxAbsValue) {
  int bits = 0;
  detail::check(pn_sat_fraction_bits(static_cast<pn_sat_precision>(precision), maxBoxTexels, maxAbsValue, &bits));
  return bits;
}

/// Levels `firstLevel`.. of a width x height base (pn_pyramid_layout).
inline PyramidLayout pyramidLayout(uint32_t width, uint32_t height, uint32_t firstLevel) {
  PyramidLayout layout;
  size_t count = 0;
  detail::check(pn_pyramid_layout(width, height, firstLevel, nullptr, 0, &count, &layout.texels));
  layout.levels.resize(count);
  detail::check(pn_pyramid_layout(width, height, firstLevel, layout.levels.data(), count, &count, nullptr));
  return layout;
}

/// Mip levels 1.. of `base` into `mips` (pn_moment_mips).
inline void momentMips(const Context& context, cl_mem base, const ImageShape& shape, MomentStorage storage, cl_mem mips,
                       const std::vector<cl_event>& waitFor = {}, cl_event* event = nullptr) {
  const pn_image_shape s = shape.toC();
  detail::check(pn_moment_mips(context.get(), base, &s, static_cast<pn_moment_storage>(storage), mips,
                               detail::waitCount(waitFor), detail::waitList(waitFor), event));
}

/// The min-max pyramid of `depth` into `out` (pn_minmax_pyramid).
inline void minMaxPyramid(const Context& context, cl_mem depth, uint32_t width, uint32_t height, cl_mem out,
                          const std::vector<cl_event>& waitFor = {}, cl_event* event = nullptr) {
  detail::check(pn_minmax_pyramid(context.get(), depth, width, height, out, detail::waitCount(waitFor),
                                  detail::waitList(waitFor), event));
}

/// Per-cluster Lloyd statistics of (x, w) into `out` (pn_lloyd_stats_reduce).
inline void lloydStats(const Context& context, cl_mem x, cl_mem w, size_t count, cl_mem boundaries, uint32_t clusters,
                       cl_mem out, const std::vector<cl_event>& waitFor = {}, cl_event* event = nullptr) {
  detail::check(pn_lloyd_stats_reduce(context.get(), x, w, count, boundaries, clusters, out, detail::waitCount(waitFor),
                                      detail::waitList(waitFor), event));
}

/// Copies width x height texels of `texelFloats` four-byte words from `src`'s layout (offset, row pitch, row order;
/// or a cl_image2d) into `dst`'s: an engine's image packed for a stage, or a stage's result unpacked (pn_image_copy).
inline void imageCopy(const Context& context, const pn_device_image& src, const pn_device_image& dst, uint32_t width,
                      uint32_t height, uint32_t texelFloats, const std::vector<cl_event>& waitFor = {},
                      cl_event* event = nullptr) {
  detail::check(pn_image_copy(context.get(), &src, &dst, width, height, texelFloats, detail::waitCount(waitFor),
                              detail::waitList(waitFor), event));
}

}  // namespace v0
}  // namespace penumbra
