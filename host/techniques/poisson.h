// Poisson-disk tap patterns for filtered shadow lookups (pcf): deterministic, the same on every platform.
#pragma once

#include <CL/cl_platform.h>

#include <cstdint>
#include <vector>

namespace penumbra {

// `count` points in the unit disk by Mitchell's best-candidate algorithm ("Spectrally optimal sampling for
// distribution ray tracing", SIGGRAPH 1991): each new point is, of `candidates` uniform candidates, the one
// farthest from the points already placed. Candidates come from a fixed 32-bit generator (PCG32), so the
// pattern depends only on (count, seed). Sorted by distance from the centre. Throws std::invalid_argument
// for count < 1.
std::vector<cl_float2> poissonDisk(int count, uint64_t seed = 1, int candidates = 64);

}  // namespace penumbra
