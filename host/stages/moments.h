// Moments stage: turns a rasterized light depth map into filterable moments (VSM, EVSM2/4, LVSM layers,
// MSM with the quantization transform). Invalid depth (NaN, +-INFINITY background) becomes the far value
// before any warp, so it can never spread NaN through the blur. Kernels: kernels/moments.cl.
#pragma once

#include <CL/opencl.hpp>
#include <cstdint>
#include <vector>

#include "host/cl/buffer.h"
#include "host/cl/context.h"
#include "kernels/shared/moments.h"

namespace penumbra {

enum class MomentKind { Vsm, Evsm2, Evsm4, Lvsm, Msm };

// Where the moments will be stored; only bounds the EVSM exponents (see evsmMaxExponent).
enum class MomentStorage { Float32, Float16 };

// One LVSM layer: the interval [p, q] of normalised depth it resolves (p < q).
struct LvsmLayer {
  float p = 0.0f, q = 1.0f;
};

struct MomentsConfig {
  MomentKind kind = MomentKind::Vsm;
  float depthNear = 0.0f, depthFar = 1.0f;          // light depth mapped to [0, 1]; far > near, both finite
  float evsmPositive = 40.0f, evsmNegative = 5.0f;  // requested EVSM exponents, clamped to the storage
  MomentStorage storage = MomentStorage::Float32;
  std::vector<LvsmLayer> layers;  // LVSM only: 1..MOMENTS_MAX_LAYERS layers
};

// 42 for fp32, 5.54 for half: the largest c with e^(2c) and its box sums representable.
float evsmMaxExponent(MomentStorage storage);
float evsmClampExponent(float exponent, MomentStorage storage);  // into [0, evsmMaxExponent]

uint32_t momentChannels(MomentKind kind);            // floats per texel of one plane: 2 or 4
uint32_t momentPlanes(const MomentsConfig& config);  // LVSM: layer count; otherwise 1

// The kernel arguments of `config` over a width x height map (validates; throws std::invalid_argument).
MomentsParams momentsParams(const MomentsConfig& config, uint32_t width, uint32_t height);
// MOMENTS_KIND_* of a single-plane encoding (throws for LVSM).
int momentsKindId(MomentKind kind);

// Writes momentPlanes * width * height * momentChannels floats to `out` (texel-interleaved; LVSM plane-major).
// `depth` holds width*height light depths. Launch named "moments/moments_<kind>".
cl::Event computeMoments(Context& ctx, const Buffer<float>& depth, uint32_t width, uint32_t height,
                         const MomentsConfig& config, Buffer<float>& out);

// 16-bit unorm storage for moments in [0, 1] (LVSM layers): out[outOffset + i] = round(clamp(in[i], 0, 1)
// * 65535) (to nearest even; NaN -> 0) for i < count; read back as value / 65535. Launch named
// "moments/moments_pack_unorm16".
cl::Event packMomentsUnorm16(Context& ctx, const Buffer<float>& in, size_t count, Buffer<cl_ushort>& out,
                             size_t outOffset = 0);

}  // namespace penumbra
