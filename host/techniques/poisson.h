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
// for count < 1. Nearest neighbours are searched in a grid of the points placed (Grid), which gives the exhaustive
// search's (Exhaustive, the reference the tests compare with) patterns bit for bit, in O(count) instead of
// O(count^2) time per point.
enum class NeighbourSearch { Grid, Exhaustive };
inline constexpr int kPoissonCandidates = 64;  // best-candidate's candidates per point, by default
std::vector<cl_float2> poissonDisk(int count, uint64_t seed = 1, int candidates = kPoissonCandidates,
                                   NeighbourSearch search = NeighbourSearch::Grid);
// The same points in the order the algorithm places them: every prefix is itself a best-candidate pattern (the first
// k points are poissonDisk(k, seed)'s, unsorted), for filters that take a different number of taps per pixel.
std::vector<cl_float2> progressivePoissonDisk(int count, uint64_t seed = 1);

}  // namespace penumbra
