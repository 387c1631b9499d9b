// Reduce stage host wrapper: fixes the work split from the sample count, then records the two passes.
#include "host/stages/reduce.h"

#include <fmt/format.h>

#include <algorithm>
#include <stdexcept>

#include "host/cl/kernel.h"
#include "host/stages/image_shape.h"

namespace penumbra {

ReduceParams planLloydReduction(size_t count, uint32_t clusters) {
  if (clusters < 1 || clusters > REDUCE_MAX_CLUSTERS)
    throw std::invalid_argument(fmt::format("reduce: {} clusters (1..{})", clusters, REDUCE_MAX_CLUSTERS));
  if (count > UINT32_MAX) throw std::invalid_argument(fmt::format("reduce: {} samples (at most 2^32 - 1)", count));
  ReduceParams p{};
  p.count = static_cast<uint32_t>(count);
  p.clusters = clusters;
  // At least 4 samples per work-item before the tree, at most REDUCE_MAX_GROUPS groups.
  const size_t perGroup = std::max<size_t>(4 * REDUCE_GROUP, (count + REDUCE_MAX_GROUPS - 1) / REDUCE_MAX_GROUPS);
  p.groups = static_cast<uint32_t>(std::max<size_t>(1, (count + perGroup - 1) / perGroup));
  p.chunk = static_cast<uint32_t>(perGroup);
  return p;
}

std::vector<cl::Event> reduceLloydStats(Context& ctx, const Buffer<float>& x, const Buffer<float>& w, size_t count,
                                        const Buffer<float>& boundaries, uint32_t clusters, Buffer<LloydStats>& out) {
  const ReduceParams p = planLloydReduction(count, clusters);
  checkBufferSize(x.size(), count, "reduce", "x");
  checkBufferSize(w.size(), count, "reduce", "w");
  checkBufferSize(boundaries.size(), clusters - 1, "reduce", "boundaries");
  checkBufferSize(out.size(), clusters, "reduce", "output");
  Buffer<LloydStats> partials(ctx, size_t(p.groups) * clusters);
  std::vector<cl::Event> events;
  const std::string options = fmt::format("-DREDUCE_CLUSTERS={}", clusters);  // one program per cluster count
  Kernel partial(ctx, "kernels/reduce.cl", "reduce_lloyd_partial", "reduce", options);
  events.push_back(partial.args(x, w, boundaries, p, partials)
                       .moves(uint64_t{count} * 2 * sizeof(float))  // floor: read x and w once
                       .launch(size_t(p.groups) * REDUCE_GROUP, REDUCE_GROUP));
  Kernel finish(ctx, "kernels/reduce.cl", "reduce_lloyd_final", "reduce", options);
  events.push_back(finish.args(partials, p, out).launch(REDUCE_GROUP, REDUCE_GROUP));
  return events;
}

}  // namespace penumbra
