// VSSM map preparation: plans the buffers, SAT storage and quad-tree, then records moments -> SAT and
// normalised depth -> min-max pyramid as named passes.
#include "host/techniques/vssm_maps.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <stdexcept>
#include <vector>

#include "host/cl/kernel.h"
#include "host/stages/image_shape.h"
#include "host/stages/moments.h"
#include "host/stages/pyramid.h"
#include "host/stages/sat.h"

namespace penumbra {
namespace {

// Fraction bits of a fixed-point table: every box the shading kernel reads sums (z, z^2) in [0, 1] over at most
// the whole table (fixed64) or a (2 maxRadius + 2)^2 box (fixed32: the corners of the widest kernel; maxRadius in
// the table's texels).
int fractionBits(VssmSatMode mode, uint32_t width, uint32_t height, float maxRadius) {
  const double texels = double(width) * height;
  if (mode == VssmSatMode::Fixed64) return satFractionBits(SAT_MODE_FIXED64, texels, 1.0);
  if (mode != VssmSatMode::Fixed32) return -1;
  const double side = 2.0 * std::ceil(maxRadius) + 2.0;
  return satFractionBits(SAT_MODE_FIXED32, std::min(texels, side * side), 1.0);
}

}  // namespace

std::vector<VssmNode> vssmQuadTree(uint32_t height) {
  if (height < 1 || height > VSSM_MAX_LEVELS)
    throw std::invalid_argument(fmt::format("vssm: quad-tree height {} outside 1..{}", height, VSSM_MAX_LEVELS));
  std::vector<VssmNode> nodes;
  // Depth-first: a node's first child follows it, and its Next is whatever follows its whole subtree.
  auto add = [&](auto& self, uint32_t x, uint32_t y, uint32_t level) -> void {
    const uint32_t index = static_cast<uint32_t>(nodes.size());
    nodes.push_back({x | (y << 16), level, VSSM_NO_NODE, 0});
    if (level < height) {
      nodes[index].child = index + 1;
      for (uint32_t k = 0; k < 4; ++k) self(self, 2 * x + (k & 1), 2 * y + (k >> 1), level + 1);
    }
    nodes[index].next = static_cast<uint32_t>(nodes.size());
  };
  add(add, 0, 0, 0);
  return nodes;
}

std::vector<float> vssmDiskStripTable() {
  // The integral of sqrt(1 - y^2) from 0 to y.
  const auto integral = [](double y) { return 0.5 * (y * std::sqrt(std::max(1.0 - y * y, 0.0)) + std::asin(y)); };
  std::vector<float> table;
  for (int strips = 1; strips <= VSSM_MAX_DISK_STRIPS; ++strips)
    for (int k = 0; k < strips; ++k) {
      const double height = 2.0 / strips, ya = -1.0 + height * k, yb = std::min(ya + height, 1.0);
      table.push_back(static_cast<float>((integral(yb) - integral(ya)) / height));
    }
  return table;
}

std::string VssmMaps::buildOptions() const { return satBuildOptions(desc_); }

template <class T>
void VssmMaps::buildSat(Context& ctx, int fractionBits) {
  const ImageShape shape{desc_.width, desc_.height, 2};
  desc_ = penumbra::satDesc(shape, satMode<T>(), fractionBits);
  if (!std::holds_alternative<Buffer<T>>(sat_) || std::get<Buffer<T>>(sat_).size() != shape.count())
    sat_ = Buffer<T>(ctx, shape.count());
  SatConfig config;
  config.fractionBits = fractionBits;
  computeSat(ctx, moments_, shape, std::get<Buffer<T>>(sat_), satOffset_, config);
}

void VssmMaps::build(Context& ctx, const Buffer<float>& depth, uint32_t width, uint32_t height, float zNear, float zFar,
                     const VssmMapConfig& config) {
  buildHsm(ctx, depth, width, height);
  buildMoments(ctx, depth, width, height, zNear, zFar, config);
}

cl_float2 VssmMaps::buildHsm(Context& ctx, const Buffer<float>& depth, uint32_t width, uint32_t height,
                             const Buffer<uint32_t>* casterFree) {
  checkShape({width, height, 1}, "vssm");
  checkBufferSize(depth.size(), size_t{width} * height, "vssm", "depth");
  return hsm_.build(ctx, depth, width, height, casterFree);
}

uint32_t vssmWindowReach(float maxRadius, uint32_t block) {
  return static_cast<uint32_t>(std::ceil(2.0f * maxRadius)) + 2 * block + 2;
}

float vssmWidestKernel(const LightViewGpu& lv, float maxRadius) {
  const double texel = lv.texelScale, near = lv.zNear, far = lv.zFar, size = lv.lightSize;
  const double widest =
      lv.kind == LIGHT_KIND_SPOT ? size * (1.0 / near - 1.0 / far) / texel : size * (far - near) / texel;
  if (!(near > 0.0 || lv.kind != LIGHT_KIND_SPOT) || !(widest >= 0.0) || !std::isfinite(widest)) return maxRadius;
  return std::clamp(static_cast<float>(widest * 1.001 + 0.01), 0.5f, maxRadius);
}

TexelWindow vssmCastersWindow(const std::array<int, 4>& casterBox, uint32_t width, uint32_t height, uint32_t reach,
                              uint32_t block) {
  if (block == 0) throw std::invalid_argument("vssm: a window of blocks of 0 texels");
  if (casterBox[0] >= casterBox[2] || casterBox[1] >= casterBox[3])
    return {0, 0, std::min(block, width), std::min(block, height)};
  const auto lo = [&](int64_t edge) { return std::max<int64_t>(0, (edge - int64_t{reach}) / block * block); };
  const auto hi = [&](int64_t edge, uint32_t size) {
    const int64_t widened = edge + reach;
    return std::min<int64_t>(size, (widened + block - 1) / block * block);
  };
  const int64_t ax = std::min<int64_t>(lo(casterBox[0]), width - 1),
                ay = std::min<int64_t>(lo(casterBox[1]), height - 1);
  const int64_t bx = std::max(hi(casterBox[2], width), ax + 1), by = std::max(hi(casterBox[3], height), ay + 1);
  return {static_cast<uint32_t>(ax), static_cast<uint32_t>(ay), static_cast<uint32_t>(bx - ax),
          static_cast<uint32_t>(by - ay)};
}

void VssmMaps::buildMoments(Context& ctx, const Buffer<float>& depth, uint32_t width, uint32_t height, float zNear,
                            float zFar, const VssmMapConfig& config) {
  // Plan: sizes, link table.
  checkShape({width, height, 1}, "vssm");
  checkBufferSize(depth.size(), size_t{width} * height, "vssm", "depth");
  if (config.satReduce < 1 || config.satReduce > kMaxMomentsReduction)
    throw std::invalid_argument(
        fmt::format("vssm: SAT reduction {} outside 1..{}", config.satReduce, kMaxMomentsReduction));
  satReduce_ = config.satReduce;
  window_ = windowOf(config.window, width, height);
  const ImageShape shape{reducedExtent(window_.width, satReduce_), reducedExtent(window_.height, satReduce_), 2};
  if (moments_.size() != shape.count()) moments_.allocate(ctx, shape.count());
  if (satOffset_.empty()) satOffset_.allocate(ctx, 4);
  if (treeHeight_ != config.treeHeight || nodes_.empty()) {
    const std::vector<VssmNode> tree = vssmQuadTree(config.treeHeight);
    nodes_ = Buffer<VssmNode>(ctx, std::span<const VssmNode>(tree), CL_MEM_READ_ONLY);
    nodeCount_ = static_cast<uint32_t>(tree.size());
    treeHeight_ = config.treeHeight;
  }
  if (strips_.empty()) {
    const std::vector<float> table = vssmDiskStripTable();
    strips_ = Buffer<float>(ctx, std::span<const float>(table), CL_MEM_READ_ONLY);
  }
  zNear_ = zNear;
  invRange_ = 1.0f / (zFar - zNear);
  desc_.width = shape.width;
  desc_.height = shape.height;
  const int bits =
      fractionBits(config.sat, shape.width, shape.height, config.maxRadius / static_cast<float>(satReduce_));

  // Record: L2 moments, L3 SAT.
  MomentsConfig moments;
  moments.kind = MomentKind::Vsm;
  moments.depthNear = zNear;
  moments.depthFar = zFar;
  if (satReduce_ == 1)
    computeMoments(ctx, depth, width, height, moments, moments_, window_);
  else
    computeMomentsReduced(ctx, depth, width, height, moments, satReduce_, moments_, window_);
  switch (config.sat) {
    case VssmSatMode::Fixed64:
      buildSat<uint64_t>(ctx, bits);
      break;
    case VssmSatMode::Fixed32:
      buildSat<uint32_t>(ctx, bits);
      break;
    case VssmSatMode::Float32:
      buildSat<float>(ctx, bits);
      break;
    case VssmSatMode::Float64:
      buildSat<double>(ctx, bits);
      break;
  }
}

}  // namespace penumbra
