// Reduce stage: weighted per-cluster statistics for Lloyd relaxation (per cluster sum w, sum w x,
// sum w x^2 and the sample count) without float atomics, bitwise reproducible. Kernels: kernels/reduce.cl.
#pragma once

#include <CL/opencl.hpp>
#include <cstddef>
#include <vector>

#include "host/cl/buffer.h"
#include "host/cl/context.h"
#include "kernels/shared/reduce.h"

namespace penumbra {

// The work split for `count` samples: fixed by the count alone (never by the device), so that the order
// of additions, and hence the result, is the same on every run.
ReduceParams planLloydReduction(size_t count, uint32_t clusters);

// Statistics of samples (x[i], w[i]), i < count, by cluster: cluster k holds the x with exactly k of the
// `clusters - 1` ascending `boundaries` <= x. Samples with non-finite x or w, or w <= 0, are skipped.
// `out` receives `clusters` LloydStats. Launches "reduce/reduce_lloyd_partial" and "reduce/reduce_lloyd_final".
// Accumulation is fp32: per work-item serial sums of <= count / 65536 samples, then pairwise trees.
std::vector<cl::Event> reduceLloydStats(Context& ctx, const Buffer<float>& x, const Buffer<float>& w, size_t count,
                                        const Buffer<float>& boundaries, uint32_t clusters, Buffer<LloydStats>& out);

}  // namespace penumbra
