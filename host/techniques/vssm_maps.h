// The per-map inputs of variance soft shadow mapping (Yang et al. 2010, Algorithm 1 L1-L5): the light's depth ->
// VSM moments normalised over [zNear, zFar] (host/stages/moments.h) -> their summed-area table
// (host/stages/sat.h, storage selectable) and the depth's min-max pyramid above the map, the mip-map HSM of sec. 6.1
// (host/stages/pyramid.h computeMinMaxLevels: lookups read level 0 from the map and normalise what they read,
// kernels/shared/vssm_lookup.h, so the HSM needs neither a normalised copy nor [zNear, zFar]); plus the Child/Next
// link table of the adaptive subdivision's quad-tree.
#pragma once

#include <CL/opencl.hpp>
#include <array>
#include <cstdint>
#include <string>
#include <variant>
#include <vector>

#include "host/cl/buffer.h"
#include "host/cl/context.h"
#include "host/stages/moments.h"
#include "host/stages/pyramid.h"
#include "kernels/shared/light_view.h"
#include "kernels/shared/pyramid.h"
#include "kernels/shared/sat.h"
#include "kernels/shared/vssm.h"

namespace penumbra {

// SAT storage (sec. 6.4 and docs/sat-precision.md): 64-bit fixed point is exact for every box of any map up to
// 32768^2, 32-bit fixed point (the paper's, after Lauritzen 2007) exact only with fewer fraction bits as boxes
// grow, fp32 offset to zero mean, fp64 on devices that have it.
enum class VssmSatMode { Fixed64 = 0, Fixed32 = 1, Float32 = 2, Float64 = 3 };

struct VssmMapConfig {
  VssmSatMode sat = VssmSatMode::Fixed64;
  float maxRadius = 128.0f;  // texels: the widest box looked up, which bounds fixed32's fraction bits
  uint32_t treeHeight = 3;   // H of the adaptive subdivision, 1..VSSM_MAX_LEVELS
  // Beyond the paper: the moments and their SAT over blocks of satReduce x satReduce texels
  // (computeMomentsReduced), 1..kMaxMomentsReduction; 1 = one SAT texel per map texel (the paper's).
  uint32_t satReduce = 1;
  // Beyond the paper: the window of the map the moments and their SAT cover (empty: the whole map; vssmCastersWindow).
  TexelWindow window;
  bool operator==(const VssmMapConfig&) const = default;
};

// Nodes of the full quad-tree of height H in depth-first order, with Child and Next links (sec. 5.3, Fig. 5(b)).
std::vector<VssmNode> vssmQuadTree(uint32_t height);

// Beyond the paper: the half-widths of a disk kernel's K equal-height strips (kernels/vssm.cl vssm_kernel_box), as
// shares of the disk's half-width w: strip k spans rows y in [-1 + 2k / K, -1 + 2 (k + 1) / K] (times w), and its
// half-width is the mean of the half chord sqrt(1 - y^2) over them, so the strips have the disk's area row by row.
// Entry K (K - 1) / 2 + k, for K = 1 .. VSSM_MAX_DISK_STRIPS.
std::vector<float> vssmDiskStripTable();

// Beyond the paper: how far around the casters the moments and their SAT are wanted. With the HSM of the casters a
// pixel reads the SAT only for a box whose square held a texel of a tile a caster reaches; such a box lies within 2
// maxRadius (its widest side) of that tile, plus the block reads' rounding: ceil(2 maxRadius) + 2 block + 2 texels.
uint32_t vssmWindowReach(float maxRadius, uint32_t block);
// The widest half-width in texels any kernel of a map with view `lv` can take: kernels/vssm.cl clamps
// lv_penumbra_texels to [0.5, maxRadius], and by similar triangles that penumbra is widest for a receiver at the far
// plane under a caster at the near plane (a spot's R (1 / z_o - 1 / z_r) / texelScale grows with z_r and shrinks as
// z_o grows; a sun's R (z_r - z_o) / texelScale likewise), with a little slack for the kernel's float rounding.
float vssmWidestKernel(const LightViewGpu& lv, float maxRadius);
// The window of a width x height map that covers `casterBox` (RasterTargets::casterBox: the tiles the casters reach,
// [x0, x1) x [y0, y1) as {x0, y0, x1, y1}) widened by `reach` texels each way and aligned outwards to blocks of `block`
// texels, within the map; the smallest window, one block, where the box is empty (no caster drawn: nothing is read).
// A kernel box that meets a caster's tile lies inside it when `reach` is vssmWindowReach's for its block, so the
// moments of the texels outside are never wanted for one (kernels/shared/vssm_lookup.h).
TexelWindow vssmCastersWindow(const std::array<int, 4>& casterBox, uint32_t width, uint32_t height, uint32_t reach,
                              uint32_t block);

class VssmMaps {
 public:
  using SatBuffer = std::variant<Buffer<uint64_t>, Buffer<uint32_t>, Buffer<float>, Buffer<double>>;

  // buildHsm, then buildMoments.
  void build(Context& ctx, const Buffer<float>& depth, uint32_t width, uint32_t height, float zNear, float zFar,
             const VssmMapConfig& config);
  // The "pyramid/pyramid_minmax_batch" passes for a width x height map of linear light depth (+INFINITY empty), the
  // texels of `casterFree`'s tiles (RasterTargets::casterFreeTiles, optional) taken as empty: levels of the casters
  // alone. Returns the drawn depth range of what they hold (min, max; +INFINITY where nothing is drawn), waiting for
  // it: what MapNear::Drawn would have reduced the map for.
  cl_float2 buildHsm(Context& ctx, const Buffer<float>& depth, uint32_t width, uint32_t height,
                     const Buffer<uint32_t>* casterFree = nullptr);
  // "moments/moments_vsm" over [zNear, zFar] (moments_vsm_reduced with a satReduce above 1: the SAT then has
  // ceil(width / satReduce) x ceil(height / satReduce) texels) and the "sat/..." passes, and the quad-tree's links;
  // over config.window of the map where it is not empty (then of its size).
  // Throws std::runtime_error for fp64 on a device without it.
  void buildMoments(Context& ctx, const Buffer<float>& depth, uint32_t width, uint32_t height, float zNear, float zFar,
                    const VssmMapConfig& config);

  const SatTableDesc& satDesc() const { return desc_; }
  const SatBuffer& sat() const { return sat_; }
  const Buffer<float>& satOffset() const { return satOffset_; }
  const Buffer<cl_float2>& hsm() const { return hsm_.pyramid(); }
  const Buffer<PyramidLevel>& levels() const { return hsm_.levels(); }
  const Buffer<VssmNode>& nodes() const { return nodes_; }
  const Buffer<float>& diskStrips() const { return strips_; }  // vssmDiskStripTable
  uint32_t levelCount() const { return hsm_.count(); }
  uint32_t satReduce() const { return satReduce_; }
  const TexelWindow& window() const { return window_; }  // the map texels the SAT covers (buildMoments)
  uint32_t nodeCount() const { return nodeCount_; }
  float depthNear() const { return zNear_; }
  float depthInvRange() const { return invRange_; }
  // -D options of kernels/vssm.cl for this SAT.
  std::string buildOptions() const;

 private:
  template <class T>
  void buildSat(Context& ctx, int fractionBits);

  Buffer<float> moments_, satOffset_;
  SatBuffer sat_;
  SatTableDesc desc_{};
  MinMaxLevels hsm_;
  Buffer<VssmNode> nodes_;
  Buffer<float> strips_;
  uint32_t nodeCount_ = 0, treeHeight_ = 0, satReduce_ = 1;
  TexelWindow window_;
  float zNear_ = 0.0f, invRange_ = 1.0f;
};

}  // namespace penumbra
