// Moments stage: turns a rasterized light depth map into filterable moments (VSM, EVSM2/4, LVSM layers,
// MSM with the quantization transform). Invalid depth (NaN, +-INFINITY background) becomes the far value
// before any warp, so it can never spread NaN through the blur. Kernels: kernels/moments.cl.
#pragma once

#include <CL/opencl.hpp>
#include <cstdint>
#include <string>
#include <type_traits>
#include <vector>

#include "host/cl/buffer.h"
#include "host/cl/context.h"
#include "kernels/shared/moments.h"

namespace penumbra {

// Esm: one channel, the normalised depth filtered in log space (kernels/shared/moments.h moments_log_mix), so that its
// exponent is not bounded by fp32's range.
enum class MomentKind { Vsm, Evsm2, Evsm4, Lvsm, Msm, Esm };

// How filtered moments are stored: fp32, or IEEE half (binary16, through OpenCL C 1.2's vload_half /
// vstore_half_rte, no cl_khr_fp16 needed), which halves the bytes every later pass and lookup reads. Half bounds
// the EVSM exponents (evsmMaxExponent); the stages' arithmetic is fp32 either way. Kernel builds take
// storageOptions(): "-DSTORE_HALF" for half (kernels/shared/storage.h).
enum class MomentStorage { Float32, Float16 };
std::string storageOptions(MomentStorage storage);

// The storage whose device element type is T: float (Float32) or cl_half (Float16).
template <class T>
constexpr MomentStorage storageOf() {
  static_assert(std::is_same_v<T, float> || std::is_same_v<T, cl_half>, "moments are stored as float or cl_half");
  return std::is_same_v<T, cl_half> ? MomentStorage::Float16 : MomentStorage::Float32;
}

// One LVSM layer: the interval [p, q] of normalised depth it resolves (p < q).
struct LvsmLayer {
  float p = 0.0f, q = 1.0f;
};

struct MomentsConfig {
  MomentKind kind = MomentKind::Vsm;
  float depthNear = 0.0f, depthFar = 1.0f;          // light depth mapped to [0, 1]; far > near, both finite
  float evsmPositive = 40.0f, evsmNegative = 5.0f;  // requested EVSM exponents, clamped to the storage
  float esmExponent = 80.0f;                        // ESM's c of e^(c d), d in [0, 1]: its log-space filters
  MomentStorage storage = MomentStorage::Float32;
  std::vector<LvsmLayer> layers;  // LVSM only: 1..MOMENTS_MAX_LAYERS layers
};

// 42 for fp32, 5.54 for half: the largest c with e^(2c) and its box sums representable.
float evsmMaxExponent(MomentStorage storage);
float evsmClampExponent(float exponent, MomentStorage storage);  // into [0, evsmMaxExponent]

// 1000 for fp32, 8 for half (MOMENTS_ESM_MAX_EXPONENT_*: e^(c (d - 1)) stays a normal half).
float esmMaxExponent(MomentStorage storage);
float esmClampExponent(float exponent, MomentStorage storage);  // into [0, esmMaxExponent]
// Whether ESM's map holds its depths filtered in log space (exponents outside [MOMENTS_ESM_LINEAR_MIN_EXPONENT,
// MOMENTS_ESM_LINEAR_EXPONENT]) rather than e^(c (d - 1)) filtered linearly.
bool esmLogSpace(float exponent);

uint32_t momentChannels(MomentKind kind);            // floats per texel of one plane: 1 (ESM), 2 or 4
uint32_t momentPlanes(const MomentsConfig& config);  // LVSM: layer count; otherwise 1

// Throws std::invalid_argument unless `config` bounds its EVSM exponents for half (storage Float16), as every
// stage that stores half moments needs; `stage` names the caller in the message.
void checkHalfMoments(const MomentsConfig& config, const char* stage);

// The kernel arguments of `config` over a width x height map (validates; throws std::invalid_argument).
MomentsParams momentsParams(const MomentsConfig& config, uint32_t width, uint32_t height);

// A window of a depth map: width x height texels from (x, y). The moments of a window have its size and read the map
// inside it only; the empty window (width 0) is the whole map.
struct TexelWindow {
  uint32_t x = 0, y = 0, width = 0, height = 0;
  bool operator==(const TexelWindow&) const = default;
};
// `window` of a width x height map as it is read (the whole map for the empty window); throws std::invalid_argument
// for one that leaves the map.
TexelWindow windowOf(const TexelWindow& window, uint32_t width, uint32_t height);
// MOMENTS_KIND_* of a single-plane encoding (throws for LVSM).
int momentsKindId(MomentKind kind);

// Writes momentPlanes * width * height * momentChannels floats to `out` (texel-interleaved; LVSM plane-major).
// `depth` holds width*height light depths. Launch named "moments/moments_<kind>". With a `window` (not LVSM): the
// moments of those texels, window.width * window.height of them.
cl::Event computeMoments(Context& ctx, const Buffer<float>& depth, uint32_t width, uint32_t height,
                         const MomentsConfig& config, Buffer<float>& out, const TexelWindow& window = {});
// The same moments stored as half (rounded to nearest even): any kind but LVSM, config.storage Float16 (so that
// EVSM exponents keep e^(2c) finite in half).
cl::Event computeMoments(Context& ctx, const Buffer<float>& depth, uint32_t width, uint32_t height,
                         const MomentsConfig& config, Buffer<cl_half>& out);

// The moments of factor x factor blocks of the map (fp32): texel (x, y) of a ceil(width / factor) x
// ceil(height / factor) grid is the mean of the moments of map texels [x f, x f + f) x [y f, y f + f), those beyond the
// map counting as empty. The encodings are linear in what is averaged, so a box of whole blocks of this grid has the
// moments of that box of the map: a summed-area table of it answers the wide boxes of a filter at 1/f^2 of the
// texels (vssm's --vssm-sat-reduce). Any kind but LVSM (one plane per layer) and ESM filtered in log space (its stored
// d is not averaged linearly); factor 1..kMaxMomentsReduction. Launch named "moments/moments_<kind>_reduced".
inline constexpr uint32_t kMaxMomentsReduction = 64;
uint32_t reducedExtent(uint32_t extent, uint32_t factor);  // ceil(extent / factor)
// With a `window`: the blocks of the window, from its origin (beyond its edge texels count as empty, as beyond the
// map).
cl::Event computeMomentsReduced(Context& ctx, const Buffer<float>& depth, uint32_t width, uint32_t height,
                                const MomentsConfig& config, uint32_t factor, Buffer<float>& out,
                                const TexelWindow& window = {});

// 16-bit unorm storage for moments in [0, 1] (LVSM layers): out[outOffset + i] = round(clamp(in[i], 0, 1)
// * 65535) (to nearest even; NaN -> 0) for i < count; read back as value / 65535. Launch named
// "moments/moments_pack_unorm16".
cl::Event packMomentsUnorm16(Context& ctx, const Buffer<float>& in, size_t count, Buffer<cl_ushort>& out,
                             size_t outOffset = 0);

// Half storage of `count` fp32 values: out[i] = in[i] rounded to the nearest even half (beyond +-65504:
// +-INFINITY). Launch named "moments/moments_pack_half".
cl::Event packMomentsHalf(Context& ctx, const Buffer<float>& in, size_t count, Buffer<cl_half>& out);

}  // namespace penumbra
