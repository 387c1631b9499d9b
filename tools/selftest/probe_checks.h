// Checks through the probe kernels (tools/selftest/kernels/): the SAT's box lookups (kernels/shared/sat.h) against the
// exact integral, MSM's decoding against its encoding, and the 16-bit unorm packing of LVSM's moments. The test suite
// (tests/sat_test.cpp, tests/moments_test.cpp) and `penumbra selftest` run the same; the context must hold the probes.
#pragma once

#include <cstdint>

#include "host/cl/context.h"
#include "tools/selftest/reference/tolerance.h"

namespace penumbra::selftest {

// Error of a box sum: at most 4 table entries' error per corner difference (the 16 bilinear weights sum to 1),
// quantization of every covered texel, and fp32 weighting of the differences: 16 fp32 products of differences,
// relative to the texels they span.
inline constexpr double kSatLookupRelTol = 2e-6;

// Box sums and means over 205 boxes (inside, across and outside a 61x47 image, empty and degenerate ones) from a
// table of element type T (float, uint32_t, uint64_t, double) with `channels` channels. Throws NotApplicable for fp64
// without cl_khr_fp64.
template <class T>
ref::Comparison satLookup(Context& ctx, uint32_t channels);

// 257 depths encoded by the reference (Peters and Klein 2015), decoded on the device: the four powers of the depth
// within ref::kMsmRoundTripTol.
ref::Comparison msmDecode(Context& ctx);

// LVSM's 16-bit unorm packing of ~1000 values (0, 1, out of range, NaN, infinities, ties) behind an offset: at most one
// code from the reference (fp32 rounds to nearest even, the reference in double with ties away), all but 5 exact, the
// first 7 (no ties) exact, nothing written before the offset.
ref::Comparison packUnorm16(Context& ctx);

}  // namespace penumbra::selftest
