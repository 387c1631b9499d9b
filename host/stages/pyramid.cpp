// Pyramid stage host wrapper: plans the level layout, then records one downsampling launch per level.
#include "host/stages/pyramid.h"

#include <fmt/format.h>

#include <algorithm>

#include "host/cl/kernel.h"

namespace penumbra {
namespace {

const Range kGroup(16, 8);

}  // namespace

PyramidLayout pyramidLayout(uint32_t width, uint32_t height, uint32_t firstLevel) {
  checkShape({width, height, 1}, "pyramid");
  PyramidLayout layout;
  layout.firstLevel = firstLevel;
  if (width == 0 || height == 0) return layout;
  for (uint32_t level = 0;; ++level) {
    if (level >= firstLevel) {
      layout.levels.push_back({static_cast<uint32_t>(layout.texels), width, height, 0});
      layout.texels += size_t(width) * height;
    }
    if (width == 1 && height == 1) break;
    width = std::max(1u, width / 2);
    height = std::max(1u, height / 2);
  }
  return layout;
}

std::vector<cl::Event> computeMomentMips(Context& ctx, const Buffer<float>& base, const ImageShape& shape,
                                         Buffer<float>& mips) {
  checkShape(shape, "pyramid");
  const PyramidLayout layout = pyramidLayout(shape.width, shape.height, 1);
  checkBufferSize(base.size(), shape.count(), "pyramid", "base level");
  checkBufferSize(mips.size(), layout.texels * shape.channels, "pyramid", "mip chain");
  Kernel down(ctx, "kernels/pyramid.cl", "pyramid_downsample", "pyramid",
              fmt::format("-DPYRAMID_CHANNELS={}", shape.channels));
  std::vector<cl::Event> events;
  PyramidLevel source{0, shape.width, shape.height, 0};
  const Buffer<float>* src = &base;
  for (const PyramidLevel& level : layout.levels) {
    // Floor: read the source level and write this one, once each.
    const uint64_t bytes = (uint64_t{source.width} * source.height + uint64_t{level.width} * level.height) *
                           shape.channels * sizeof(float);
    events.push_back(
        down.args(*src, source, mips, level).moves(bytes).launch(Range(level.width, level.height), kGroup));
    source = level;
    src = &mips;
  }
  return events;
}

std::vector<cl::Event> computeMinMaxPyramid(Context& ctx, const Buffer<float>& depth, uint32_t width, uint32_t height,
                                            Buffer<cl_float2>& out) {
  const PyramidLayout layout = pyramidLayout(width, height, 0);
  checkBufferSize(depth.size(), size_t(width) * height, "pyramid", "depth");
  checkBufferSize(out.size(), layout.texels, "pyramid", "min-max pyramid");
  std::vector<cl::Event> events;
  if (layout.levels.empty()) return events;
  const std::string options = "-DPYRAMID_CHANNELS=1";  // the same program as 1-channel mips
  Kernel base(ctx, "kernels/pyramid.cl", "pyramid_minmax_base", "pyramid", options);
  // Floors: the base reads the depth map and writes level 0 (a float2 per texel); each further level reads the
  // level above and writes itself.
  const auto texels = [](const PyramidLevel& l) { return uint64_t{l.width} * l.height; };
  events.push_back(base.args(depth, out, layout.levels[0])
                       .moves(uint64_t{width} * height * sizeof(float) + texels(layout.levels[0]) * sizeof(cl_float2))
                       .launch(Range(width, height), kGroup));
  Kernel down(ctx, "kernels/pyramid.cl", "pyramid_minmax_down", "pyramid", options);
  for (size_t i = 1; i < layout.levels.size(); ++i) {
    const PyramidLevel& level = layout.levels[i];
    events.push_back(down.args(out, layout.levels[i - 1], out, level)
                         .moves((texels(layout.levels[i - 1]) + texels(level)) * sizeof(cl_float2))
                         .launch(Range(level.width, level.height), kGroup));
  }
  return events;
}

}  // namespace penumbra
