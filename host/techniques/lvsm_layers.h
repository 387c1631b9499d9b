// LVSM layer placement (Lauritzen & McCool, GI 2008, sec. 3.4 and 4): split sequences (uniform, manual), the
// widened layer intervals, Lloyd relaxation of the splits as a 1-D weighted k-means on "second occluder"
// depths (sec. 4.1) with the cluster sums reduced on the device (host/stages/reduce.h) and split
// teleportation (sec. 5), and our light-space leak metric used to choose the layer count.
#pragma once

#include <string>
#include <vector>

#include "host/cl/buffer.h"
#include "host/cl/context.h"
#include "kernels/shared/lvsm.h"

namespace penumbra {

// s_0 = 0, s_i = i / N, s_N = 1.
std::vector<float> uniformSplits(int layers);
// "0.2,0.5" -> {0, 0.2, 0.5, 1}: interior splits strictly increasing inside (0, 1), at most
// MOMENTS_MAX_LAYERS - 1 of them. Throws std::invalid_argument naming the bad entry.
std::vector<float> parseSplits(const std::string& text);
std::string formatSplits(const std::vector<float>& splits);  // interior splits, "0.2,0.5"

// The layout the kernels read: layers L_i = [s_{i-1} - delta, s_i + delta] clamped to [0, 1] (sec. 3.4; the
// first and last keep s_0 and s_N), transition half-width tau <= delta around each interior split.
LvsmLayout lvsmLayout(const std::vector<float>& splits, bool uniform, float overlap, float transition,
                      float minVariance, float leakGap);

// The 2x2-neighbourhood samples of a depth map, normalised over [depthNear, depthFar]:
// (width - 1) * (height - 1) of them, one per bilinear sample between four texels.
struct LvsmSamples {
  Buffer<float> x, w;
  size_t count = 0;
};
void lloydSamples(Context& ctx, const Buffer<float>& depth, uint32_t width, uint32_t height, float depthNear,
                  float depthFar, float minVariance, LvsmSamples& out);

struct LloydConfig {
  int maxIterations = 16;   // stopping rule: at most this many updates ...
  float tolerance = 1e-3f;  // ... or stop once no split moves farther than this (normalised depth)
  bool teleport = true;     // sec. 5: an empty cluster's split moves into the heaviest layer
  // Sec. 5's per-frame schedule: each iteration moves only `splitsPerIteration` interior splits (0: all), the
  // first of them `firstSplit` (0-based among the interior ones, counted modulo their number), the others after
  // it in order. Teleportation still applies to any empty cluster.
  int splitsPerIteration = 0;
  size_t firstSplit = 0;
  bool operator==(const LloydConfig&) const = default;
};
struct LloydResult {
  std::vector<float> splits;  // s_0..s_N
  int iterations = 0, teleports = 0;
  float lastMove = 0.0f;
  bool converged = false;
};

// Lloyd relaxation of the interior splits of `start` (s_0..s_N) on samples (x, w): each split is the centre
// of the samples nearer to it than to its neighbours (boundaries at the midpoints), and moves to their
// weighted mean. Cluster sums come from reduceLloydStats; the host only reads N - 1 sums per iteration.
LloydResult lloydRelax(Context& ctx, const LvsmSamples& samples, std::vector<float> start, const LloydConfig& config);

// Adds one split inside the layer with the largest sample weight, at its weighted mean (sec. 5's "split the
// heaviest"). Returns false (splits unchanged) when no layer holds weight away from its ends.
bool splitHeaviestLayer(Context& ctx, const LvsmSamples& samples, std::vector<float>& splits);

// Our leak metric for a layout: over the map's 2x2 neighbourhoods with variance above sigma^2_min, the
// variance-weighted mean of the layered Chebyshev bound for a receiver layout.leakGap behind the
// neighbourhood's farthest depth (true visibility 0), i.e. the expected bleeding behind depth
// discontinuities, weighted as the Lloyd samples are. 0 when the map has no discontinuity.
double lvsmLeak(Context& ctx, const Buffer<float>& depth, uint32_t width, uint32_t height, float depthNear,
                float depthFar, const LvsmLayout& layout);

}  // namespace penumbra
