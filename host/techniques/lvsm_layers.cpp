// LVSM layer placement: split sequences, layer intervals with overlaps (sec. 3.4), Lloyd relaxation with
// teleportation (sec. 4.1, 5) over device-reduced cluster sums, and the leak metric.
#include "host/techniques/lvsm_layers.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>

#include "host/cl/kernel.h"
#include "host/stages/reduce.h"

namespace penumbra {
namespace {

// Splits closer than this (normalised depth) to each other or to 0 and 1 are pushed apart: a layer must
// keep q > p, and a split at 0 or 1 resolves nothing.
constexpr float kMinGap = 1e-4f;

MomentsParams mapParams(uint32_t width, uint32_t height, float depthNear, float depthFar) {
  MomentsParams p{};
  p.width = width;
  p.height = height;
  p.pitch = width;
  p.layerCount = 1;
  p.depthNear = depthNear;
  p.depthInvRange = 1.0f / (depthFar - depthNear);
  return p;
}

size_t sampleCount(uint32_t width, uint32_t height) {
  return width < 2 || height < 2 ? 0 : size_t(width - 1) * (height - 1);
}

// Per-cluster sums of the samples for ascending `boundaries` (clusters = boundaries + 1).
std::vector<LloydStats> clusterStats(Context& ctx, const LvsmSamples& samples, const std::vector<float>& boundaries) {
  const auto clusters = static_cast<uint32_t>(boundaries.size() + 1);
  Buffer<float> bounds(ctx, std::max<size_t>(boundaries.size(), 1));
  if (!boundaries.empty()) bounds.upload(ctx, std::span<const float>(boundaries));
  Buffer<LloydStats> out(ctx, clusters);
  reduceLloydStats(ctx, samples.x, samples.w, samples.count, bounds, clusters, out);
  return out.download(ctx);
}

// Sorted, inside [kMinGap, 1 - kMinGap], at least kMinGap apart; s_0 = 0 and s_N = 1 kept.
void tidy(std::vector<float>& s) {
  std::sort(s.begin() + 1, s.end() - 1);
  for (size_t i = 1; i + 1 < s.size(); ++i)
    s[i] = std::clamp(std::max(s[i], s[i - 1] + kMinGap), kMinGap, 1.0f - kMinGap * float(s.size() - i));
}

}  // namespace

std::vector<float> uniformSplits(int layers) {
  std::vector<float> s(size_t(layers) + 1);
  for (int i = 0; i <= layers; ++i) s[size_t(i)] = static_cast<float>(i) / static_cast<float>(layers);
  return s;
}

std::vector<float> parseSplits(const std::string& text) {
  std::vector<float> s = {0.0f};
  std::stringstream in(text);
  std::string item;
  while (std::getline(in, item, ',')) {
    size_t used = 0;
    float v = NAN;
    try {
      v = std::stof(item, &used);
    } catch (const std::exception&) {
      used = 0;
    }
    if (used == 0 || used != item.size() || !(v > s.back()) || !(v < 1.0f))
      throw std::invalid_argument(fmt::format(
          "--lvsm-splits: '{}' is not a number in ({}, 1) (splits are increasing normalised depths)", item, s.back()));
    s.push_back(v);
  }
  if (s.size() > MOMENTS_MAX_LAYERS)
    throw std::invalid_argument(
        fmt::format("--lvsm-splits: {} splits (at most {})", s.size() - 1, MOMENTS_MAX_LAYERS - 1));
  s.push_back(1.0f);
  return s;
}

std::string formatSplits(const std::vector<float>& splits) {
  std::string text;
  for (size_t i = 1; i + 1 < splits.size(); ++i) text += fmt::format("{}{:.6g}", text.empty() ? "" : ",", splits[i]);
  return text;
}

LvsmLayout lvsmLayout(const std::vector<float>& splits, bool uniform, float overlap, float transition,
                      float minVariance, float leakGap) {
  const size_t n = splits.size() - 1;
  if (n < 1 || n > MOMENTS_MAX_LAYERS) throw std::invalid_argument(fmt::format("lvsm: {} layers", n));
  LvsmLayout l{};
  l.count = static_cast<uint32_t>(n);
  l.uniform = uniform ? 1u : 0u;
  l.transition = std::min(transition, overlap);
  l.minVariance = minVariance;
  l.leakGap = leakGap;
  for (size_t i = 0; i <= n; ++i) l.split[i] = splits[i];
  for (size_t i = 0; i < n; ++i) {
    l.layer[2 * i] = i == 0 ? 0.0f : std::max(0.0f, splits[i] - overlap);
    l.layer[2 * i + 1] = i + 1 == n ? 1.0f : std::min(1.0f, splits[i + 1] + overlap);
  }
  return l;
}

void lloydSamples(Context& ctx, const Buffer<float>& depth, uint32_t width, uint32_t height, float depthNear,
                  float depthFar, float minVariance, LvsmSamples& out) {
  out.count = sampleCount(width, height);
  out.x.allocate(ctx, out.count);
  out.w.allocate(ctx, out.count);
  if (out.count == 0) return;
  Kernel kernel(ctx, "kernels/lvsm_splits.cl", "lvsm_lloyd_samples", "lvsm");
  kernel.args(depth, mapParams(width, height, depthNear, depthFar), minVariance, out.x, out.w)
      .moves(uint64_t{width} * height * 4 + uint64_t{out.count} * 8)  // depth in, (x, w) samples out
      .launch(Range(width - 1, height - 1), Range(16, 8));
}

bool splitHeaviestLayer(Context& ctx, const LvsmSamples& samples, std::vector<float>& splits) {
  if (samples.count == 0 || splits.size() > MOMENTS_MAX_LAYERS) return false;
  const std::vector<float> interior(splits.begin() + 1, splits.end() - 1);
  const std::vector<LloydStats> layers = clusterStats(ctx, samples, interior);
  size_t heaviest = 0;
  for (size_t i = 1; i < layers.size(); ++i)
    if (layers[i].sumW > layers[heaviest].sumW) heaviest = i;
  if (!(layers[heaviest].sumW > 0.0f)) return false;
  const float mean = layers[heaviest].sumWX / layers[heaviest].sumW;
  if (!(mean > splits[heaviest] + kMinGap && mean < splits[heaviest + 1] - kMinGap)) return false;
  splits.insert(splits.begin() + static_cast<long>(heaviest) + 1, mean);
  return true;
}

namespace {

// Whether interior split i of k moves this iteration (LloydConfig::splitsPerIteration, firstSplit).
bool updated(size_t i, size_t k, const LloydConfig& config) {
  if (config.splitsPerIteration <= 0 || static_cast<size_t>(config.splitsPerIteration) >= k) return true;
  return (i + k - config.firstSplit % k) % k < static_cast<size_t>(config.splitsPerIteration);
}

}  // namespace

LloydResult lloydRelax(Context& ctx, const LvsmSamples& samples, std::vector<float> start, const LloydConfig& config) {
  LloydResult r;
  r.splits = std::move(start);
  const size_t k = r.splits.size() - 2;  // interior splits = clusters
  if (k == 0 || samples.count == 0) return r;
  tidy(r.splits);
  const int maxTeleports = 2 * static_cast<int>(k);
  while (r.iterations < config.maxIterations) {
    std::vector<float> boundaries;
    for (size_t i = 1; i < k; ++i) boundaries.push_back(0.5f * (r.splits[i] + r.splits[i + 1]));
    const std::vector<LloydStats> stats = clusterStats(ctx, samples, boundaries);
    ++r.iterations;
    // Teleportation (sec. 5): a split whose cluster holds no weight merges its two layers; the heaviest
    // layer is split instead.
    auto empty = std::find_if(stats.begin(), stats.end(), [](const LloydStats& s) { return !(s.sumW > 0.0f); });
    if (config.teleport && empty != stats.end() && r.teleports < maxTeleports) {
      std::vector<float> merged = r.splits;
      merged.erase(merged.begin() + 1 + (empty - stats.begin()));
      if (splitHeaviestLayer(ctx, samples, merged)) {
        r.splits = merged;
        ++r.teleports;
        r.converged = false;
        continue;
      }
    }
    std::vector<float> next = r.splits;
    for (size_t i = 0; i < k; ++i)
      if (stats[i].sumW > 0.0f && updated(i, k, config)) next[i + 1] = stats[i].sumWX / stats[i].sumW;
    tidy(next);
    r.lastMove = 0.0f;
    for (size_t i = 1; i <= k; ++i) r.lastMove = std::max(r.lastMove, std::abs(next[i] - r.splits[i]));
    r.splits = next;
    if (r.lastMove < config.tolerance) {
      r.converged = true;
      break;
    }
  }
  return r;
}

double lvsmLeak(Context& ctx, const Buffer<float>& depth, uint32_t width, uint32_t height, float depthNear,
                float depthFar, const LvsmLayout& layout) {
  LvsmSamples leak;
  leak.count = sampleCount(width, height);
  if (leak.count == 0) return 0.0;
  leak.x.allocate(ctx, leak.count);
  leak.w.allocate(ctx, leak.count);
  Buffer<LvsmLayout> layoutBuffer(ctx, std::span<const LvsmLayout>(&layout, 1), CL_MEM_READ_ONLY);
  Kernel kernel(ctx, "kernels/lvsm_splits.cl", "lvsm_leak_samples", "lvsm");
  kernel.args(depth, mapParams(width, height, depthNear, depthFar), layoutBuffer, leak.x, leak.w)
      .moves(uint64_t{width} * height * 4 + uint64_t{leak.count} * 8)  // depth in, (x, w) samples out
      .launch(Range(width - 1, height - 1), Range(16, 8));
  const LloydStats s = clusterStats(ctx, leak, {}).front();
  return s.sumW > 0.0f ? double(s.sumWX) / double(s.sumW) : 0.0;
}

}  // namespace penumbra
